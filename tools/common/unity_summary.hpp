#pragma once
// UnitySummaryWatch: finds the end of a Unity test run in what a firmware
// sends (ThrowTheSwitch's Unity, the test framework of `pio test`).
//
// Unity's UNITY_END() prints (unity.c, UnityEnd):
//   -----------------------
//   3 Tests 1 Failures 0 Ignored
//   FAIL
// the counts line, then "OK" or "FAIL" on a line of its own, each line ended
// by UNITY_PRINT_EOL ('\n', or "\r\n" where a port defines it so). The run is
// complete when the OK/FAIL line has ended.

#include <cstdint>
#include <optional>
#include <string>

namespace ddmr::tools {

struct UnitySummary {
    uint32_t tests = 0;
    uint32_t failures = 0;
    uint32_t ignored = 0;
    bool ok = false;  ///< Unity's last line: OK (true) or FAIL
};

class UnitySummaryWatch {
public:
    /// Feeds one received byte; true once, when the summary has ended.
    bool feed(char c);
    [[nodiscard]] const std::optional<UnitySummary>& summary() const { return summary_; }
    /// The counts line was seen but not yet its OK/FAIL line.
    [[nodiscard]] bool counts_seen() const { return counts_.has_value(); }

private:
    void on_line(const std::string& line);

    std::string line_;
    std::optional<UnitySummary> counts_;
    std::optional<UnitySummary> summary_;
};

}  // namespace ddmr::tools
