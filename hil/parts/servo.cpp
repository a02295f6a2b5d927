// A hobby servo (SG90 class) on a pan mount (../shared/SENSORS.md section 6):
//   - it reads the HIGH pulses on its signal pin; a pulse of min_us..max_us
//     means 0..180 degrees, linearly: the Arduino Servo library's mapping
//     (Servo.h: MIN_PULSE_WIDTH 544, MAX_PULSE_WIDTH 2400; write(90) sends
//     map(90, 0, 180, 544, 2400) = 1472 us, not 1500). Wider or narrower
//     pulses are clamped to the end stops;
//   - the horn turns toward that angle at `slew_deg_s` (SG90: 0.1 s per 60
//     degrees at 4.8 V, 600 deg/s [SG90]);
//   - a change of less than the dead band (SG90: 10 us) is ignored;
//   - when the pulses stop, it holds its position (unverified);
//   - the pulses may come from port writes (the Servo library's interrupt,
//     a digitalWrite loop) or from a timer's compare output (OC1A in fast
//     PWM with ICR1 as TOP, for example): a pin with an OC unit is decoded by
//     PinWaveforms, and while the unit drives it the pulse width is the
//     waveform's high time per period, read at each coupling step;
//   - at power-on it stands at `start_deg`.
// Its angle is a truth column; 90 degrees points along the mount's
// heading_deg (0 degrees is to its right, 180 to its left, as a servo seen
// from above with its horn up). A sensor may sit on the horn (its `mount:
// NAME` key): it turns with the horn, carried_mount().

#include <algorithm>
#include <cmath>
#include <memory>

#include "hil/cycle_time.hpp"
#include "hil/pin_waveforms.hpp"
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "plant/units.hpp"

namespace ddmr::hil {
namespace {

class Servo final : public Part {
public:
    explicit Servo(const PartContext& ctx)
        : core_(ctx.core()), min_us_(ctx.number("min_us")), max_us_(ctx.number("max_us")),
          slew_deg_s_(ctx.number("slew_deg_s")), dead_band_us_(ctx.number("dead_band_us")),
          from_deg_(ctx.number("start_deg")), target_deg_(from_deg_), axis_(mount_of(ctx, true)), none_(ctx.name()) {
        ctx.input("SIGNAL").add_listener([this](bool level, Cycles cycle) { on_signal(level, cycle); });
        const std::optional<int> pin = ctx.wired_pin("SIGNAL");
        if (pin && board_pin(core_.board(), *pin)->oc) {
            pin_ = *pin;
            oc_channel_ = board_pin(core_.board(), pin_)->oc->channel;
            oc_.emplace(core_, std::vector<int>{pin_});
        }
    }

    /// A pulse the pin's OC unit makes: its high time per period.
    void on_plant_step(Cycles cycle) override {
        if (!oc_) return;
        oc_->advance_to(cycle);
        if (!oc_->timer_driven(pin_)) return;
        const Cycles period = oc_->timer_of(pin_)->period_cycles(oc_channel_);
        if (period == 0) return;  // a constant level: no pulses, the horn holds
        const double high_cycles = oc_->duty(pin_) * static_cast<double>(period);
        apply_width(cycles_to_s(static_cast<Cycles>(std::llround(high_cycles)), core_.clock_hz()) * 1e6, cycle);
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"angle_deg", "pulse_us"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(angle_deg(core_.cycle()));
        out.push_back(last_pulse_us_);
    }

    /// A part on the horn: at the horn's axis, pointing along heading_deg
    /// turned by (angle - 90) degrees (90 degrees: straight along heading_deg).
    std::optional<SensorMount> carried_mount(Cycles cycle) const override {
        SensorMount m = axis_;
        m.heading_rad += (angle_deg(cycle) - 90.0) * plant::kPi / 180.0;
        return m;
    }

private:
    /// The horn's angle at `cycle`: from from_deg_ (at from_cycle_) toward the target at the slew rate.
    [[nodiscard]] double angle_deg(Cycles cycle) const {
        const double moved = slew_deg_s_ * cycles_to_s(cycle - std::min(cycle, from_cycle_), core_.clock_hz());
        if (target_deg_ >= from_deg_) return std::min(target_deg_, from_deg_ + moved);
        return std::max(target_deg_, from_deg_ - moved);
    }

    void on_signal(bool level, Cycles cycle) {
        if (level) {
            rise_ = cycle;
            return;
        }
        apply_width(cycles_to_s(cycle - rise_, core_.clock_hz()) * 1e6, cycle);
    }

    /// A pulse of `width_us` ended at `cycle`: the horn turns toward its angle.
    void apply_width(double width_us, Cycles cycle) {
        if (std::fabs(width_us - last_pulse_us_) < dead_band_us_) return;
        last_pulse_us_ = width_us;
        from_deg_ = angle_deg(cycle);
        from_cycle_ = cycle;
        target_deg_ = std::clamp((width_us - min_us_) / (max_us_ - min_us_), 0.0, 1.0) * 180.0;
    }

    AvrCore& core_;
    double min_us_, max_us_, slew_deg_s_, dead_band_us_;
    double from_deg_;
    Cycles from_cycle_ = 0;
    double target_deg_;
    Cycles rise_ = 0;
    double last_pulse_us_ = 0.0;
    SensorMount axis_;
    DrivenSignal none_;
    int pin_ = -1;
    int oc_channel_ = 0;              ///< the pin's OCnx channel (0 = A)
    std::optional<PinWaveforms> oc_;  ///< the SIGNAL pin's waveform, when it has an OC unit
};

std::optional<PartKeyProblem> check(const PartEntry& e, const BoardDescription& /*board*/) {
    if (std::stod(e.values.at("min_us").text) >= std::stod(e.values.at("max_us").text)) {
        return PartKeyProblem{"max_us", "must be more than min_us"};
    }
    return std::nullopt;
}

}  // namespace

PartType servo_type() {
    PartType t;
    t.type = "servo";
    t.summary = "hobby servo (SG90 class): its angle follows the signal's pulse width at the servo's slew rate";
    t.datasheet = "TowerPro SG90 (0.1 s/60 deg, dead band 10 us); Arduino Servo library (544-2400 us for 0-180 deg)";
    t.keys = {PartKey::input("SIGNAL", "the control signal: a HIGH pulse every 20 ms, its width the angle")};
    for (PartKey& k : mount_keys("the horn's axis", true, 60)) {
        if (k.kind == PartKeyKind::carrier) continue;  // a servo sits on the chassis
        if (k.name == "heading_deg") {
            k.description = "where the horn points at 90 degrees, counter-clockwise from straight ahead [deg] "
                            "(0 degrees points 90 to its right, 180 to its left)";
        }
        t.keys.push_back(std::move(k));
    }
    t.keys.push_back(PartKey::number("min_us", "the pulse width for 0 degrees [us]", 544, 100, 5000));
    t.keys.push_back(PartKey::number("max_us", "the pulse width for 180 degrees [us]", 2400, 100, 5000));
    t.keys.push_back(PartKey::number("slew_deg_s", "how fast the horn turns [deg/s]", 600, 1, 100000));
    t.keys.push_back(PartKey::number("dead_band_us", "a change of pulse width smaller than this is ignored [us]", 10, 0,
                                     100));
    t.keys.push_back(PartKey::number("start_deg", "the horn's angle at power-on [deg]", 90, 0, 180));
    t.carries_parts = true;
    t.create = [](const PartContext& ctx) { return std::make_unique<Servo>(ctx); };
    t.check = check;
    return t;
}

}  // namespace ddmr::hil
