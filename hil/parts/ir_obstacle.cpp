// An IR obstacle module (FC-51 style: an IR LED and photodiode behind an
// LM393 comparator; ../shared/SENSORS.md section 3, module-specific, no
// manufacturer datasheet): OUT is "normally high" and goes LOW while an
// obstacle lies within the range set by its potentiometer (2-30 cm, [SF];
// Waveshare: detection angle 35 degrees [VEND]). Here: LOW while a wall lies
// within `range_cm` of the module inside a cone of `cone_deg` (default 35)
// about its axis, checked at every plant step. The module drives its pin
// (the comparator's pull-up is on the board). Left out: the range's
// dependence on the obstacle's colour (shortest on black) and sunlight.

#include <memory>

#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "hil/pin_driver.hpp"

namespace ddmr::hil {
namespace {

class IrObstacle final : public Part {
public:
    explicit IrObstacle(const PartContext& ctx)
        : pose_(ctx.pose_source()), world_(ctx.world()), placement_(ctx), pin_(ctx.output_pin("OUT")),
          range_m_(ctx.number("range_cm") * 1e-2), half_angle_rad_(ctx.number("cone_deg") * plant::kPi / 360.0),
          active_low_(ctx.text("active") == "low"), driver_(ctx.core()), none_(ctx.name()) {
        detected_ = sees(ctx.core().cycle());
        driver_.drive_now(pin_, level());
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"detected"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(detected_ ? 1.0 : 0.0); }
    void set_reading(const std::string& /*name*/, std::optional<double> value) override { held_ = value; }
    void on_plant_step(Cycles pose_cycle) override {
        const bool detected = sees(pose_cycle);
        if (detected == detected_) return;
        detected_ = detected;
        driver_.schedule(pin_, pose_cycle, level());
    }

private:
    [[nodiscard]] bool sees(Cycles cycle) const {
        if (held_) return *held_ >= 0.5;
        const plant::Pose pose = pose_();
        const SensorMount mount = placement_.at(cycle);
        plant::Cone cone;
        cone.origin_m = world_point(pose, mount);
        cone.direction_rad = world_heading_rad(pose, mount);
        cone.half_angle_rad = half_angle_rad_;
        cone.max_incidence_rad = plant::kPi / 2;  // diffuse reflection: any angle returns light
        cone.max_range_m = range_m_;
        return plant::cast_cone(world_, cone).has_value();
    }
    [[nodiscard]] bool level() const { return detected_ != active_low_; }

    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    SensorPlacement placement_;
    int pin_;
    double range_m_;
    double half_angle_rad_;
    bool active_low_;
    PinDriver driver_;
    DrivenSignal none_;
    bool detected_ = false;
    std::optional<double> held_;  ///< set_reading's detection
};

}  // namespace

PartType ir_obstacle_type() {
    PartType t;
    t.type = "ir-obstacle";
    t.readings = {{"detected", "1: an obstacle in range, 0: none", 0.0, 1.0}};
    t.summary = "IR obstacle module (FC-51 style): OUT LOW while a wall is within its set range";
    t.datasheet = "module-specific: SunFounder avoidance module page (2-30 cm, normally high, LOW on an obstacle); "
                  "Waveshare (35 degrees)";
    t.keys = {PartKey::output("OUT", "the module's digital output")};
    for (PartKey& k : mount_keys("the module's", true, 90)) t.keys.push_back(std::move(k));
    t.keys.push_back(PartKey::number("range_cm", "the range its potentiometer is set to [cm]", 15, 1, 100));
    t.keys.push_back(PartKey::number("cone_deg", "the detection angle, full [deg]", 35, 1, 120));
    t.keys.push_back(PartKey::choice("active", "low (OUT LOW on an obstacle, FC-51) or high", {"low", "high"}));
    t.create = [](const PartContext& ctx) { return std::make_unique<IrObstacle>(ctx); };
    t.check = [](const PartEntry& e, const BoardDescription& /*board*/) { return check_mount(e); };
    return t;
}

}  // namespace ddmr::hil
