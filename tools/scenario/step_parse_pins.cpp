// The steps on the board's pins (step_parsers.hpp): wait-pin, expect-pin, expect-pwm.
#include "scenario/step_parsers.hpp"

namespace ddmr::tools::scenario::yaml {

std::optional<StepAction> parse_pin_step(const std::string& kind, const Ctx& c) {
    if (kind == "wait-pin") {
        c.keys({"pin", "value", "timeout"}, {"pin", "value"});
        return WaitPin{board_pin(c.child("pin")), c.child("value").boolean(),
                       c.has("timeout") ? c.child("timeout").duration() : 0};
    }
    if (kind == "expect-pin") {
        c.keys({"pin", "value"}, {"pin", "value"});
        return ExpectPin{board_pin(c.child("pin")), c.child("value").boolean()};
    }
    if (kind == "expect-pwm") {
        c.keys({"pin", "duty", "tol"}, {"pin", "duty"});
        return ExpectPwm{pwm_pin(c.child("pin")), c.child("duty").number_in(0, 1, "[0, 1]"),
                         c.has("tol") ? c.child("tol").number_in(0, 1, "[0, 1]") : 0.01};
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
