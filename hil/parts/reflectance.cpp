// A reflectance (line) sensor under the chassis: the floor's reflectance
// under its spot (plant/reflectance_sensor.hpp) as one of the three outputs
// kit modules have (../shared/SENSORS.md section 2):
//   digital  an LM393 comparator module (TCRT5000 boards: SunFounder and
//            Keyestudio high on black [SF], [VEND]; DFRobot SEN0017 low on
//            black): a level, changed at the plant step where the spot crosses
//            `threshold`;
//   analog   a QTR-A or a module's AO pin: a voltage on an ADC pin
//            (AdcInput), `white_v` on white, `black_v` on black tape;
//   rc       a QTR-RC line ([QTRAN] section 2; [QTRLIB] read()): while the
//            firmware drives the pin high, the sensor's capacitor charges;
//            when it makes the pin an input (pull-up off), the pin reads high
//            for the decay time over the floor under the spot, then low. A
//            charge shorter than the 10 us the application note asks for
//            gives a proportionally shorter decay (a model choice). An input
//            with the pull-up on reads high.
// The floor is read at each plant step (every 62.5 us by default): an edge
// lands at the cycle of the pose that crossed the threshold.

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <optional>

#include "hil/adc_input.hpp"
#include "hil/cycle_time.hpp"
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "hil/pin_driver.hpp"
#include "hil/pin_probe.hpp"
#include "plant/reflectance_sensor.hpp"

namespace ddmr::hil {
namespace {

constexpr double kFullChargeS = 10e-6;  // [QTRAN] section 2: "allow at least 10 us"

enum class Output : uint8_t { digital, analog, rc };

Output output_of(const std::string& text) {
    if (text == "analog") return Output::analog;
    return text == "rc" ? Output::rc : Output::digital;
}

class Reflectance final : public Part {
public:
    explicit Reflectance(const PartContext& ctx)
        : core_(ctx.core()), pose_(ctx.pose_source()), world_(ctx.world()), mount_(mount_of(ctx, false)),
          output_(output_of(ctx.text("output"))), pin_(ctx.output_pin("OUT")), spot_m_(ctx.number("spot_mm") * 1e-3),
          threshold_(ctx.number("threshold")), high_on_dark_(ctx.text("active") == "high-on-dark"),
          analog_{ctx.number("white_v"), ctx.number("black_v"), ctx.core().board().supply_v},
          rc_{ctx.number("white_decay_us") * 1e-6, ctx.number("black_decay_us") * 1e-6}, none_(ctx.name()) {
        reflectance_ = read_floor();
        switch (output_) {
            case Output::digital:
                driver_ = std::make_unique<PinDriver>(core_);
                level_ = comparator(reflectance_);
                driver_->drive_now(pin_, level_);
                break;
            case Output::analog:
                adc_ = std::make_unique<AdcInput>(core_);
                adc_->set_voltage(pin_, [this](Cycles) { return plant::analog_output_v(analog_, reflectance_); });
                break;
            case Output::rc:
                driver_ = std::make_unique<PinDriver>(core_);
                probe_ = std::make_unique<PinProbe>(core_, pin_);
                driver_->drive_now(pin_, false);  // discharged
                probe_->set_listener([this](const PinState& s, Cycles c) { on_pin(s, c); });
                break;
        }
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override {
        switch (output_) {
            case Output::digital: return {"reflectance", "level"};
            case Output::analog: return {"reflectance", "volts"};
            case Output::rc: break;
        }
        return {"reflectance", "decay_us"};
    }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(reflectance_);
        switch (output_) {
            case Output::digital: out.push_back(level_ ? 1.0 : 0.0); return;
            case Output::analog: out.push_back(plant::analog_output_v(analog_, reflectance_)); return;
            case Output::rc: out.push_back(last_decay_us_); return;
        }
    }
    void set_reading(const std::string& /*name*/, std::optional<double> value) override { held_ = value; }
    void on_plant_step(Cycles pose_cycle) override {
        reflectance_ = read_floor();
        if (output_ != Output::digital) return;
        const bool level = comparator(reflectance_);
        if (level == level_) return;
        level_ = level;
        driver_->schedule(pin_, pose_cycle, level);
    }

private:
    [[nodiscard]] double read_floor() const {
        if (held_) return *held_;
        return plant::spot_reflectance(world_, world_point(pose_(), mount_), spot_m_);
    }
    [[nodiscard]] bool comparator(double reflectance) const { return (reflectance < threshold_) == high_on_dark_; }

    /// The QTR-RC line: charged while driven high, decaying once an input.
    void on_pin(const PinState& s, Cycles cycle) {
        if (s.output) {
            driver_->cancel_all();
            if (!s.port_bit) {
                charged_since_.reset();  // driven low: the capacitor empties
            } else if (!charged_since_) {
                charged_since_ = cycle;
            }
            return;
        }
        if (s.pull_up) {  // pinMode(INPUT) clears DDR before PORT: the pull-up holds it high meanwhile
            driver_->drive_now(pin_, true);
            return;
        }
        if (!charged_since_) {
            driver_->drive_now(pin_, false);
            return;
        }
        const double charge = std::min(1.0, cycles_to_s(cycle - *charged_since_, core_.clock_hz()) / kFullChargeS);
        const double decay_s = charge * plant::rc_decay_s(rc_, reflectance_);
        last_decay_us_ = decay_s * 1e6;
        charged_since_.reset();
        driver_->drive_now(pin_, true);
        driver_->schedule(pin_, cycle + s_to_cycles(decay_s, core_.clock_hz()), false);
    }

    AvrCore& core_;
    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    SensorMount mount_;
    Output output_;
    int pin_;
    double spot_m_;
    double threshold_;
    bool high_on_dark_;
    plant::AnalogReflectanceParams analog_;
    plant::RcReflectanceParams rc_;
    DrivenSignal none_;
    std::unique_ptr<PinDriver> driver_;
    std::unique_ptr<PinProbe> probe_;
    std::unique_ptr<AdcInput> adc_;
    double reflectance_ = 0.0;
    std::optional<double> held_;  ///< set_reading's reflectance
    bool level_ = false;
    std::optional<Cycles> charged_since_;
    double last_decay_us_ = 0.0;
};

std::optional<PartKeyProblem> check(const PartEntry& e, const BoardDescription& board) {
    if (e.values.at("output").text == "analog") {
        try {
            (void)AdcInput::channel_of(board, e.values.at("OUT").pin);
        } catch (const std::invalid_argument& err) {
            return PartKeyProblem{"OUT", fmt::format("an analog reflectance sensor needs an ADC input: {}", err.what())};
        }
    }
    const double white = std::stod(e.values.at("white_decay_us").text);
    if (std::stod(e.values.at("black_decay_us").text) <= white) {
        return PartKeyProblem{"black_decay_us", "must be longer than white_decay_us (black returns less light)"};
    }
    return std::nullopt;
}

}  // namespace

PartType reflectance_type() {
    PartType t;
    t.type = "reflectance";
    t.readings = {{"reflectance", "the floor's reflectance under the spot (0 black .. 1 white)", 0.0, 1.0}};
    t.summary = "line sensor under the chassis: TCRT5000 comparator module (digital), QTR-A/AO (analog), QTR-RC (rc)";
    t.datasheet = "Vishay TCRT5000 doc. 83760; Pololu QTR application note 0J13 section 2 (RC decay: 780 us white, "
                  "10 ms black); SunFounder/Keyestudio/DFRobot module pages (comparator polarity)";
    t.keys = {
        PartKey::output("OUT", "the pin the module's output is wired to (analog: an ADC pin, A0..; rc: the line the "
                               "firmware charges and times)"),
        PartKey::choice("output", "digital (comparator module), analog (voltage on an ADC pin) or rc (QTR-RC decay)",
                        {"digital", "analog", "rc"}),
    };
    for (PartKey& k : mount_keys("the spot's", false, 60)) t.keys.push_back(std::move(k));
    t.keys.push_back(PartKey::number("spot_mm", "diameter of the floor disc the sensor averages [mm] (0: one point)",
                                     3, 0, 30));
    t.keys.push_back(PartKey::number("threshold", "digital: the reflectance (0..1) below which the floor counts as dark "
                                                  "(white 0.8, black tape 0.05)",
                                     0.425, 0, 1));
    t.keys.push_back(PartKey::choice("active", "digital: high-on-dark (SunFounder, Keyestudio) or low-on-dark (DFRobot)",
                                     {"high-on-dark", "low-on-dark"}));
    t.keys.push_back(PartKey::number("white_v", "analog: the output over white (reflectance 0.8) [V]", 0.3, 0, 5.5));
    t.keys.push_back(PartKey::number("black_v", "analog: the output over black tape (reflectance 0.05) [V]", 4.5, 0, 5.5));
    t.keys.push_back(PartKey::number("white_decay_us", "rc: the decay time over white [us]", 780, 1, 1e6));
    t.keys.push_back(PartKey::number("black_decay_us", "rc: the decay time over black tape [us]", 10000, 1, 1e6));
    t.create = [](const PartContext& ctx) { return std::make_unique<Reflectance>(ctx); };
    t.check = check;
    return t;
}

}  // namespace ddmr::hil
