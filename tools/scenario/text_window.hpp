#pragma once
// TextWindow: the last `capacity` bytes of a text that grows byte by byte,
// with positions counted from the text's first byte. The scenario runner keeps
// the serial output it searches (`wait-serial`, `expect-serial`) and the
// current line (`fail-serial`) in one, so a run's memory does not grow with
// its length; the whole output is streamed to uart.txt instead.
//
// Memory: at most 2 x capacity bytes (the buffer drops its oldest `capacity`
// bytes when it holds twice that), so appending costs O(1) amortised.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace ddmr::tools::scenario {

class TextWindow {
public:
    /// `capacity` >= 1 [bytes]: how much of the end of the text view() shows.
    explicit TextWindow(std::size_t capacity);

    void push_back(char c);
    /// Forgets the text: size() is 0 again.
    void clear();

    /// Bytes appended since construction or clear(), including those dropped.
    uint64_t size() const { return dropped_ + buffer_.size(); }
    bool empty() const { return size() == 0; }
    std::size_t capacity() const { return capacity_; }
    /// The last min(size(), capacity()) bytes.
    std::string_view view() const;
    /// Position (in the whole text) of view()'s first byte.
    uint64_t view_begin() const { return size() - view().size(); }
    /// Position of the first `needle` that starts at or after `from` and lies
    /// wholly in view(); nullopt if there is none.
    std::optional<uint64_t> find(std::string_view needle, uint64_t from) const;
    /// True if the text ends with `needle` (and needle fits in view()).
    bool ends_with(std::string_view needle) const;

private:
    std::size_t capacity_;
    std::string buffer_;  ///< the text from position dropped_ on
    uint64_t dropped_ = 0;
};

}  // namespace ddmr::tools::scenario
