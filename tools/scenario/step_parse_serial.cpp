// The steps of time and text (step_parsers.hpp): delay, write-serial, wait-serial,
// expect-serial, fail-serial, expect-warning.
#include "scenario/step_parsers.hpp"

namespace ddmr::tools::scenario::yaml {

std::optional<StepAction> parse_serial_step(const std::string& kind, const Ctx& c) {
    if (kind == "delay") return Delay{c.duration()};
    if (kind == "write-serial") return WriteSerial{c.str()};
    if (kind == "wait-serial") {
        if (c.node().IsScalar()) return WaitSerial{c.str(), 0};
        c.keys({"text", "timeout"}, {"text"});
        return WaitSerial{c.child("text").str(), c.has("timeout") ? c.child("timeout").duration() : 0};
    }
    if (kind == "expect-serial" || kind == "fail-serial" || kind == "expect-warning") {
        const std::string pattern = c.str();
        check_regex(c, pattern);
        if (kind == "fail-serial") return FailSerial{pattern};
        if (kind == "expect-warning") return ExpectWarning{pattern};
        return ExpectSerial{pattern};
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
