#include "common/unity_summary.hpp"

#include <regex>

namespace ddmr::tools {

namespace {
constexpr std::size_t kMaxLine = 512;  // a longer line is no summary line: cut (bounded memory)
}

bool UnitySummaryWatch::feed(char c) {
    if (summary_) return false;
    if (c != '\n') {
        if (c != '\r' && line_.size() < kMaxLine) line_.push_back(c);
        return false;
    }
    on_line(line_);
    line_.clear();
    return summary_.has_value();
}

void UnitySummaryWatch::on_line(const std::string& line) {
    static const std::regex counts(R"(^\s*([0-9]+) Tests ([0-9]+) Failures ([0-9]+) Ignored\s*$)");
    std::smatch m;
    if (std::regex_match(line, m, counts)) {
        UnitySummary s;
        s.tests = static_cast<uint32_t>(std::stoul(m[1].str()));
        s.failures = static_cast<uint32_t>(std::stoul(m[2].str()));
        s.ignored = static_cast<uint32_t>(std::stoul(m[3].str()));
        counts_ = s;
        return;
    }
    if (!counts_) return;
    std::string word = line;
    while (!word.empty() && (word.back() == ' ' || word.back() == '\t')) word.pop_back();
    if (word == "OK" || word == "FAIL") {
        summary_ = counts_;
        summary_->ok = word == "OK";
    } else if (!word.empty()) {
        counts_.reset();  // something else followed: that was no summary
    }
}

}  // namespace ddmr::tools
