#include "scenario/text_window.hpp"

#include <algorithm>
#include <stdexcept>

namespace ddmr::tools::scenario {

TextWindow::TextWindow(std::size_t capacity) : capacity_(capacity) {
    if (capacity_ == 0) throw std::invalid_argument("TextWindow: capacity must be at least 1 byte");
}

void TextWindow::push_back(char c) {
    if (buffer_.size() >= 2 * capacity_) {
        buffer_.erase(0, capacity_);
        dropped_ += capacity_;
    }
    buffer_.push_back(c);
}

void TextWindow::clear() {
    buffer_.clear();
    dropped_ = 0;
}

std::string_view TextWindow::view() const {
    const std::string_view all(buffer_);
    return all.size() > capacity_ ? all.substr(all.size() - capacity_) : all;
}

std::optional<uint64_t> TextWindow::find(std::string_view needle, uint64_t from) const {
    const std::string_view v = view();
    const uint64_t begin = view_begin();
    const uint64_t start = std::max(from, begin) - begin;
    if (start > v.size()) return std::nullopt;
    const std::size_t at = v.find(needle, static_cast<std::size_t>(start));
    if (at == std::string_view::npos) return std::nullopt;
    return begin + at;
}

bool TextWindow::ends_with(std::string_view needle) const {
    const std::string_view v = view();
    return needle.size() <= v.size() && v.substr(v.size() - needle.size()) == needle;
}

}  // namespace ddmr::tools::scenario
