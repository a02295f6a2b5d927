// The steps that inject faults into the robot or change its world
// (step_parsers.hpp): inject, stall, battery, slip, push, place, move-obstacle, reset.
#include "scenario/step_parsers.hpp"

namespace ddmr::tools::scenario::yaml {

std::optional<StepAction> parse_fault_step(const std::string& kind, const Ctx& c) {
    if (kind == "inject") {
        c.keys({"encoder", "drop", "for"}, {"encoder", "drop"});
        return InjectDrop{wheel_number(c.child("encoder")), c.child("drop").number_in(0, 0.5, "[0, 0.5]"),
                          optional_for(c)};
    }
    if (kind == "stall") {
        c.keys({"motor", "for"}, {"motor", "for"});
        return Stall{wheel_number(c.child("motor")), c.child("for").duration()};
    }
    if (kind == "battery") {
        c.keys({"volts", "for"}, {"volts"});
        return Battery{c.child("volts").number_in(0.1, 50, "[0.1, 50] V"), optional_for(c)};
    }
    if (kind == "slip") {
        c.keys({"wheel", "traction", "for"}, {"wheel", "traction"});
        return Slip{wheel_number(c.child("wheel")), c.child("traction").number_in(0, 1, "[0, 1]"),
                    optional_for(c)};
    }
    if (kind == "push") {
        c.keys({"dx_m", "dy_m", "dtheta_rad", "over"});
        Push p;
        if (c.has("over")) p.over = c.child("over").duration();
        if (c.has("dx_m")) p.dx_m = c.child("dx_m").number_in(-10, 10, "[-10, 10] m");
        if (c.has("dy_m")) p.dy_m = c.child("dy_m").number_in(-10, 10, "[-10, 10] m");
        if (c.has("dtheta_rad")) p.dtheta_rad = c.child("dtheta_rad").number_in(-10, 10, "[-10, 10] rad");
        return p;
    }
    if (kind == "place") {
        c.keys({"x_m", "y_m", "heading_deg"}, {"x_m", "y_m", "heading_deg"});
        return Place{c.child("x_m").number_in(-1000, 1000, "[-1000, 1000] m"),
                     c.child("y_m").number_in(-1000, 1000, "[-1000, 1000] m"),
                     c.child("heading_deg").number_in(-3600, 3600, "[-3600, 3600] degrees")};
    }
    if (kind == "move-obstacle") {
        c.keys({"name", "dx_m", "dy_m", "over"}, {"name"});
        MoveObstacle m;
        m.name = c.child("name").str();
        if (c.has("dx_m")) m.dx_m = c.child("dx_m").number_in(-100, 100, "[-100, 100] m");
        if (c.has("dy_m")) m.dy_m = c.child("dy_m").number_in(-100, 100, "[-100, 100] m");
        if (c.has("over")) m.over = c.child("over").duration();
        return m;
    }
    if (kind == "reset") {
        if (!c.node().IsNull() && !(c.node().IsMap() && c.node().size() == 0)) c.fail("takes no value");
        return Reset{};
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
