// The steps on the board's pins and parts (step_parsers.hpp): wait-pin, expect-pin, expect-pwm, expect-part.
#include "scenario/step_parsers.hpp"

#include <algorithm>

#include "hil/parts/part_registry.hpp"

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
    if (kind == "expect-part") {
        c.keys({"part", "port", "value"}, {"part", "port", "value"});
        ExpectPart e{c.child("part").str(), c.child("port").str(), c.child("value").boolean()};
        if (const hil::BoardWiring* wiring = c.wiring()) {
            const auto part = std::find_if(wiring->parts.begin(), wiring->parts.end(),
                                           [&](const hil::PartEntry& p) { return p.name == e.part; });
            if (part == wiring->parts.end()) c.child("part").fail("no part is called '" + e.part + "' on the board");
            const hil::PartType* type = hil::PartRegistry::global().find(part->type);
            if (type == nullptr || !type->has_port(e.port)) {
                c.child("port").fail("part '" + e.part + "' (" + part->type + ") has no output '" + e.port + "'");
            }
        }
        return e;
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
