// A bumper: a switch from the pin to ground, closed while a wall touches the
// bumper's lever (../shared/SENSORS.md section 4):
//   - wiring: pin to GND, `pinMode(pin, INPUT_PULLUP)`: released reads HIGH
//     through the 20-50 kOhm pull-up (ATmega328P 13.2.1, 28.2 RPU), pressed
//     reads LOW;
//   - pressed: a wall within `reach_mm` of the lever's point (x_mm, y_mm: on
//     the body's edge; the lever sticks out by reach_mm, so the switch closes
//     before the body itself meets the wall);
//   - bounce: each press and each release is followed by `bounces` extra
//     changes spread evenly over `bounce_ms` (Omron tactile switches: 5 ms
//     max [OMR]; no figure for snap-action bumpers was read: 0 by default);
//   - the switch holds the pin LOW against the pull-up while the sketch
//     writes to the same port (PinDriver declares it the pin's external
//     level: simavr 1.6 would otherwise re-raise the pull-up on every write
//     to PORTx, SENSORS.md section 4);
//   - released, the pin reads HIGH while its pull-up is on; with the pull-up
//     off an open switch leaves it floating, read here as LOW (undefined on
//     the chip, 13.2.6).
// Checked at every plant step.

#include <memory>

#include "hil/cycle_time.hpp"
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "hil/pin_driver.hpp"
#include "hil/pin_probe.hpp"

namespace ddmr::hil {
namespace {

class Bumper final : public Part {
public:
    explicit Bumper(const PartContext& ctx)
        : pose_(ctx.pose_source()), world_(ctx.world()), mount_(mount_of(ctx, false)),
          pin_(ctx.output_pin("OUT")), reach_m_(ctx.number("reach_mm") * 1e-3),
          bounce_(s_to_cycles(ctx.number("bounce_ms") * 1e-3, ctx.core().clock_hz())),
          bounces_(static_cast<int>(ctx.number("bounces"))), driver_(ctx.core()), probe_(ctx.core(), pin_),
          none_(ctx.name()) {
        pressed_ = touching();
        driver_.drive_now(pin_, level(pressed_));
        probe_.set_listener([this](const PinState&, Cycles cycle) {
            if (!pressed_ && driver_.pending() == 0) driver_.schedule(pin_, cycle, level(false));
        });
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"pressed", "presses"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(pressed_ ? 1.0 : 0.0);
        out.push_back(static_cast<double>(presses_));
    }
    void set_reading(const std::string& /*name*/, std::optional<double> value) override { held_ = value; }
    void on_plant_step(Cycles pose_cycle) override {
        const bool pressed = touching();
        if (pressed == pressed_) return;
        pressed_ = pressed;
        if (pressed) ++presses_;
        driver_.cancel_all();
        // The bounce: the contact opens and closes `bounces` times, then settles.
        for (int k = 0; k < bounces_; ++k) {
            const Cycles at = pose_cycle + bounce_ * static_cast<Cycles>(k) / static_cast<Cycles>(bounces_);
            driver_.schedule(pin_, at, level(k % 2 == 0 ? pressed : !pressed));
        }
        driver_.schedule(pin_, pose_cycle + (bounces_ > 0 ? bounce_ : 0), level(pressed));
    }

private:
    [[nodiscard]] bool touching() const {
        if (held_) return *held_ >= 0.5;
        return plant::nearest_wall_distance(world_, world_point(pose_(), mount_)) <= reach_m_;
    }
    /// The pin's level: LOW while closed; open, the pull-up's (floating: LOW).
    [[nodiscard]] bool level(bool pressed) const { return !pressed && probe_.state().pull_up; }

    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    SensorMount mount_;
    int pin_;
    double reach_m_;
    Cycles bounce_;
    int bounces_;
    PinDriver driver_;
    PinProbe probe_;
    DrivenSignal none_;
    bool pressed_ = false;
    std::optional<double> held_;  ///< set_reading's switch
    uint64_t presses_ = 0;
};

}  // namespace

PartType bumper_type() {
    PartType t;
    t.type = "bumper";
    t.readings = {{"pressed", "1: the switch is closed, 0: open (bounces as a contact does)", 0.0, 1.0}};
    t.summary = "bumper switch to ground (INPUT_PULLUP): LOW while a wall touches its lever, with optional bounce";
    t.datasheet = "ATmega328P 13.2.1 and 28.2 (pull-up 20-50 kOhm); Omron B3FS/B3S (bounce 5 ms max)";
    t.keys = {PartKey::output("OUT", "the pin the switch pulls to ground (the sketch sets INPUT_PULLUP)")};
    for (PartKey& k : mount_keys("the lever's", false, 90)) t.keys.push_back(std::move(k));
    t.keys.push_back(PartKey::number("reach_mm", "how far the lever reaches beyond its point: pressed while a wall is "
                                                 "this near [mm]",
                                     5, 0, 200));
    t.keys.push_back(PartKey::number("bounce_ms", "the time the contact bounces after each change [ms]", 0, 0, 50));
    t.keys.push_back(PartKey::number("bounces", "extra changes within bounce_ms after each change", 0, 0, 20));
    t.create = [](const PartContext& ctx) { return std::make_unique<Bumper>(ctx); };
    return t;
}

}  // namespace ddmr::hil
