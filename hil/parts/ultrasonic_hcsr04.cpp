// HC-SR04 ultrasonic ranger (../shared/SENSORS.md section 1;
// plant/sonar.hpp for the echo):
//   - a HIGH on TRIG of at least 10 us starts a measurement at its falling
//     edge ([SR04] p. 1; SimulIDE and PICSimLab act on the falling edge too);
//     a shorter pulse is ignored;
//   - ECHO rises `burst_us` later (the 8 x 25 us burst, [PING] p. 2) and stays
//     high for 2 d / c, d from a cone cast from the transducers into the world
//     at the trigger's pose, c from `temperature_c`; with no echo it stays high
//     for `no_echo_us` (about 38 ms on common modules);
//   - a trigger while a measurement runs (ECHO pending or high) is ignored
//     (the datasheet asks for a 60 ms cycle; what a module does is not
//     documented).
// TRIG reads low while it floats (NewPing makes it an input between pings).

#include <fmt/format.h>

#include <algorithm>
#include <memory>

#include "hil/cycle_time.hpp"
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "hil/pin_driver.hpp"
#include "plant/sonar.hpp"

namespace ddmr::hil {
namespace {

constexpr double kMinTriggerS = 10e-6;  // [SR04] p. 1: "at least 10 us high level"

class UltrasonicHcsr04 final : public Part {
public:
    explicit UltrasonicHcsr04(const PartContext& ctx)
        : core_(ctx.core()), pose_(ctx.pose_source()), world_(ctx.world()), placement_(ctx),
          echo_pin_(ctx.output_pin("ECHO")), params_(params_of(ctx)), driver_(ctx.core()), none_(ctx.name()) {
        driver_.drive_now(echo_pin_, false);
        ctx.input("TRIG").add_listener([this](bool level, Cycles cycle) { on_trig(level, cycle); });
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"distance_m", "echo_us", "pings"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(distance_m_);
        out.push_back(echo_us_);
        out.push_back(static_cast<double>(pings_));
    }
    void set_reading(const std::string& /*name*/, std::optional<double> value) override { held_m_ = value; }

private:
    static plant::SonarParams params_of(const PartContext& ctx) {
        constexpr double kDeg = plant::kPi / 180.0;
        plant::SonarParams p;
        p.cone_full_angle_rad = ctx.number("cone_deg") * kDeg;
        p.max_incidence_rad = ctx.number("max_incidence_deg") * kDeg;
        p.min_range_m = ctx.number("min_range_m");
        p.max_range_m = ctx.number("max_range_m");
        p.temperature_c = ctx.number("temperature_c");
        p.burst_s = ctx.number("burst_us") * 1e-6;
        p.no_echo_s = ctx.number("no_echo_us") * 1e-6;
        p.mount_height_m = ctx.number("height_mm") * 1e-3;
        return p;
    }

    void on_trig(bool level, Cycles cycle) {
        if (level) {
            trig_rise_ = cycle;
            return;
        }
        if (cycle < busy_until_ || cycles_to_s(cycle - trig_rise_, core_.clock_hz()) < kMinTriggerS) return;
        const plant::Pose pose = pose_();
        const SensorMount mount = placement_.at(cycle);
        const std::optional<double> d =
            held_m_ ? held_distance_m()
                    : plant::sonar_distance_m(world_, params_, world_point(pose, mount), world_heading_rad(pose, mount));
        const double width_s = plant::echo_width_s(params_, d);
        const Cycles rise = cycle + s_to_cycles(params_.burst_s, core_.clock_hz());
        const Cycles fall = rise + s_to_cycles(width_s, core_.clock_hz());
        driver_.schedule(echo_pin_, rise, true);
        driver_.schedule(echo_pin_, fall, false);
        busy_until_ = fall;
        distance_m_ = d.value_or(0.0);
        echo_us_ = width_s * 1e6;
        ++pings_;
    }

    /// A held distance as the cone would give it: clamped up to the minimum range, none beyond the maximum.
    [[nodiscard]] std::optional<double> held_distance_m() const {
        if (*held_m_ > params_.max_range_m) return std::nullopt;
        return std::max(*held_m_, params_.min_range_m);
    }

    AvrCore& core_;
    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    SensorPlacement placement_;
    int echo_pin_;
    plant::SonarParams params_;
    PinDriver driver_;
    DrivenSignal none_;
    Cycles trig_rise_ = 0;
    Cycles busy_until_ = 0;
    double distance_m_ = 0.0;
    double echo_us_ = 0.0;
    uint64_t pings_ = 0;
    std::optional<double> held_m_;  ///< set_reading's distance
};

std::optional<PartKeyProblem> check(const PartEntry& e, const BoardDescription& /*board*/) {
    if (std::stod(e.values.at("min_range_m").text) >= std::stod(e.values.at("max_range_m").text)) {
        return PartKeyProblem{"max_range_m", "must be more than min_range_m"};
    }
    return check_mount(e);
}

}  // namespace

PartType ultrasonic_hcsr04_type() {
    PartType t;
    t.type = "ultrasonic";
    t.readings = {{"distance_m", "the distance the next pings measure [m] (past max_range_m: no echo)", 0.0, 100.0}};
    t.summary = "HC-SR04 ultrasonic ranger: TRIG pulse in, ECHO high for the sound's round trip to the nearest wall";
    t.datasheet = "ElecFreaks HC-SR04 (10 us trigger, 15 deg, 2 cm - 4 m, 58 us/cm); Parallax PING))) v2.0 "
                  "(200 us burst, c = 331.5 + 0.6 T m/s)";
    t.keys = {
        PartKey::input("TRIG", "trigger: a HIGH of at least 10 us starts a ping at its falling edge"),
        PartKey::output("ECHO", "echo: high for 2 d / c after the 200 us burst"),
    };
    for (PartKey& k : mount_keys("the transducers'", true, 70)) t.keys.push_back(std::move(k));
    t.keys.push_back(PartKey::number("height_mm", "the beam's height above the floor [mm]: lower walls are not seen", 50,
                                     0, 2000));
    t.keys.push_back(PartKey::number("cone_deg", "the beam's full angle [deg]", 15, 0.1, 120));
    t.keys.push_back(PartKey::number("max_incidence_deg",
                                     "a wall struck more obliquely (ray to wall normal) sends no echo back [deg]", 45, 0,
                                     90));
    t.keys.push_back(PartKey::number("min_range_m", "a nearer wall reads as this [m]", 0.02, 0, 10));
    t.keys.push_back(PartKey::number("max_range_m", "a farther wall sends no echo [m]", 4.0, 0.01, 50));
    t.keys.push_back(PartKey::number("temperature_c", "the air's temperature [degC] (c = 331.5 + 0.6 T m/s)", 20, -40, 85));
    t.keys.push_back(PartKey::number("burst_us", "TRIG's falling edge to ECHO's rise [us]", 200, 0, 10000));
    t.keys.push_back(PartKey::number("no_echo_us", "ECHO's width when nothing echoes [us]", 38000, 1, 1e6));
    t.create = [](const PartContext& ctx) { return std::make_unique<UltrasonicHcsr04>(ctx); };
    t.check = check;
    return t;
}

}  // namespace ddmr::hil
