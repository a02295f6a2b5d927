#pragma once
// Parts: the robot's hardware around the MCU, each created by type from the
// PartRegistry (part_registry.hpp) and wired by the board file's `parts:`
// list (docs/boards.md, "Parts"). A part type is one file: it declares
//   - its board-file keys (PartKey): inputs (a board pin, another part's
//     output "NAME.PORT", high or low), output pins it drives, and options,
//     each with a one-line description;
//   - its output ports (PartPort), which other parts read as LogicSignals
//     (a 74HC595's Q0..Q7 feed an L293D's IN1/IN2);
//   - a factory that builds the part from a PartContext.
// At run time a part reads its inputs (LogicSignal listeners, or the
// capabilities PinProbe, PinDriver, AdcInput, TwiSlave built on ctx.core(),
// docs/parts_capabilities.md), drives its outputs, and names its truth
// columns.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/logic_signal.hpp"
#include "hil/parts/wheel_part_spec.hpp"
#include "plant/robot_params.hpp"
#include "plant/world.hpp"

namespace ddmr::hil {

/// What a board-file key of a part is.
enum class PartKeyKind : uint8_t {
    input,       ///< a signal the part reads: a pin, NAME.PORT (another part's output), high or low
    output_pin,  ///< a board pin the part drives
    option,      ///< a value: a number in [lo, hi], or one of `choices`
    carrier,     ///< the name of another part this one sits on (a sonar on a servo's horn); optional
};

struct PartKey {
    std::string name;         ///< as printed on the module: "DS", "SHCP"
    PartKeyKind kind = PartKeyKind::input;
    std::string description;  ///< one line, for `ddmr-hil parts`, docs and the schema
    bool required = true;
    std::string default_value;         ///< an option's value (or an input's high/low) when left out
    std::vector<std::string> choices;  ///< an option's allowed words (empty: a number)
    double lo = 0.0, hi = 0.0;         ///< a numeric option's range

    static PartKey input(std::string name, std::string description) {
        return {std::move(name), PartKeyKind::input, std::move(description), true, {}, {}, 0.0, 0.0};
    }
    /// An input that reads `fallback` (high or low) when the board file leaves it out.
    static PartKey input_or(std::string name, std::string description, std::string fallback) {
        return {std::move(name), PartKeyKind::input, std::move(description), false, std::move(fallback), {}, 0.0, 0.0};
    }
    static PartKey output(std::string name, std::string description) {
        return {std::move(name), PartKeyKind::output_pin, std::move(description), true, {}, {}, 0.0, 0.0};
    }
    static PartKey number(std::string name, std::string description, double fallback, double lo, double hi);
    static PartKey choice(std::string name, std::string description, std::vector<std::string> choices);
    /// The part this one sits on (left out: the chassis).
    static PartKey carrier(std::string name, std::string description) {
        return {std::move(name), PartKeyKind::carrier, std::move(description), false, {}, {}, 0.0, 0.0};
    }
};

/// Where a sensor sits in the robot's frame (origin at the middle of the
/// wheel axle, x forward, y to the left; sensor_mount.hpp).
struct SensorMount {
    double x_m = 0.0;
    double y_m = 0.0;
    double heading_rad = 0.0;  ///< a directional sensor's axis (0: straight ahead)
};

/// A reading a test may hold in place of what the part sees in the world
/// (the Python API's sensor(NAME).set(KEY=VALUE), docs/python.md).
struct SettableReading {
    std::string name;         ///< with its unit: "distance_m", "reflectance"
    std::string description;  ///< one line
    double lo = 0.0, hi = 0.0;  ///< the values it takes
};

/// An output other parts can read as "NAME.PORT".
struct PartPort {
    std::string name;
    std::string description;
};

/// One `parts:` entry as the board file gives it (resolved against its type).
struct PartEntry {
    std::string name;  ///< unique on the board; other parts say NAME.PORT
    std::string type;
    int line = 0;      ///< board-file line of the entry
    struct Value {
        std::string text;  ///< as written: "8", "A0", "shield.Q2", "high", "2.5"
        int pin = -1;      ///< a pin's number (inputs and output pins on a pin)
        int line = 0;
    };
    std::map<std::string, Value> values;  ///< by key; defaults filled in
};

class Part;

/// What a part is built from: the core, its resolved inputs, output pins and options.
class PartContext {
public:
    using SignalOf = std::function<const LogicSignal&(const std::string& key)>;
    using PartOf = std::function<const Part&(const std::string& name)>;
    PartContext(AvrCore& core, const PartEntry& entry, SignalOf signal_of, std::function<plant::Pose()> pose,
                const plant::World& world, PartOf part_of = {})
        : core_(core), entry_(entry), signal_of_(std::move(signal_of)), pose_(std::move(pose)), world_(world),
          part_of_(std::move(part_of)) {}

    [[nodiscard]] AvrCore& core() const { return core_; }
    [[nodiscard]] const std::string& name() const { return entry_.name; }
    /// The signal wired to input `key`.
    [[nodiscard]] const LogicSignal& input(const std::string& key) const { return signal_of_(key); }
    /// The board pin input `key` is wired to, for a part that watches the
    /// pin's mode (PinProbe) or drives it too (an RC sensor). Throws
    /// std::invalid_argument naming the part and key when the board file
    /// wired it to another part's output or to high/low.
    [[nodiscard]] int input_pin(const std::string& key) const;
    /// The board pin input `key` is wired to, or nullopt when it is wired to
    /// another part's output or to high/low.
    [[nodiscard]] std::optional<int> wired_pin(const std::string& key) const;
    /// The board pin of output `key`.
    [[nodiscard]] int output_pin(const std::string& key) const;
    /// An option's text, or a numeric option's value.
    [[nodiscard]] const std::string& text(const std::string& key) const;
    [[nodiscard]] double number(const std::string& key) const;
    /// The robot's pose now (for parts that see the world).
    [[nodiscard]] plant::Pose pose() const { return pose_(); }
    /// The pose as a function a part keeps, to read at run time (the context
    /// itself lives only while the factory runs).
    [[nodiscard]] const std::function<plant::Pose()>& pose_source() const { return pose_; }
    /// The world around the robot (docs/world.md; empty: the plain floor).
    /// It outlives the part.
    [[nodiscard]] const plant::World& world() const { return world_; }
    /// The part carrier key `key` names (built before this one), or nullptr
    /// when the entry leaves the key out. It outlives the part.
    [[nodiscard]] const Part* carrier(const std::string& key) const;

private:
    AvrCore& core_;
    const PartEntry& entry_;
    SignalOf signal_of_;
    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    PartOf part_of_;
};

class Part {
public:
    virtual ~Part() = default;
    /// Output port `port` (one of its type's ports) as a signal.
    [[nodiscard]] virtual const LogicSignal& output(const std::string& port) const = 0;
    /// truth.csv's columns of this part (without the "NAME." prefix) and their values now.
    [[nodiscard]] virtual std::vector<std::string> truth_columns() const { return {}; }
    virtual void truth_values(std::vector<double>& /*out*/) const {}
    /// Called each time the plant has been stepped (every coupling step,
    /// 62.5 us by default), inside the simulation: `pose_cycle` is the AVR
    /// cycle the plant's state (PartContext::pose()) now stands for, one step
    /// in the AVR's future (hil/plant_coupler.hpp). A part that sees the
    /// world updates its outputs here (a PinDriver edge scheduled at
    /// `pose_cycle` lands exactly when the pose is true). Must not throw.
    virtual void on_plant_step(Cycles /*pose_cycle*/) {}
    /// A carrier (its type's `carries_parts`): where a part sitting on it is
    /// at `cycle`, in the robot's frame (a servo: its horn's axis, turned by
    /// the horn's angle then). Others: nullopt.
    [[nodiscard]] virtual std::optional<SensorMount> carried_mount(Cycles /*cycle*/) const { return std::nullopt; }
    /// What the part saw the firmware do that it does not model (an IMU's
    /// DMP registers), one line each, for the run's warnings.
    [[nodiscard]] virtual std::vector<std::string> warnings() const { return {}; }
    /// Holds reading `name` (one of its type's `readings`, `value` in range:
    /// PartSet::set_reading checks) from the next plant step on, in place of
    /// the world's; nullopt: the world's again. Must not throw.
    virtual void set_reading(const std::string& /*name*/, std::optional<double> /*value*/) {}
};

/// A board-file key of an entry its type cannot use on this board, and why.
struct PartKeyProblem {
    std::string key;
    std::string message;  ///< "pin 7 of the Arduino Uno has no ADC input (...)"
};

struct PartType {
    std::string type;       ///< the board file's `type:` word
    std::string summary;    ///< one line
    std::string datasheet;  ///< the source of its behaviour
    std::vector<PartKey> keys;
    std::vector<PartPort> ports;
    /// Where its physical parameters are set, one line ("the plant file's
    /// `l293d:` section: ..."); empty: the board-file keys are all it has.
    std::string plant_parameters;
    /// The factory; none for a wheel part (a motor driver or an encoder:
    /// read and driven by the rig, wheel_part_spec.hpp).
    std::function<std::unique_ptr<Part>(const PartContext&)> create;
    /// Checks an entry against the board when the board file is read (an
    /// analog output on a pin without an ADC input, an I2C device off the
    /// TWI pins); none: every pin the keys accept will do.
    std::function<std::optional<PartKeyProblem>(const PartEntry&, const BoardDescription&)> check;
    /// The readings a test may hold in place of the world's (Part::set_reading); empty: none.
    std::vector<SettableReading> readings;
    /// Other parts may sit on it (a carrier key names it: a servo carries a sonar).
    bool carries_parts = false;
    std::optional<MotorDriverSpec> motor_driver;  ///< set: a motor driver type
    std::optional<EncoderSpec> encoder;           ///< set: an encoder type

    [[nodiscard]] bool on_wheel() const { return motor_driver.has_value() || encoder.has_value(); }
    [[nodiscard]] const PartKey* key(const std::string& name) const;
    [[nodiscard]] bool has_port(const std::string& name) const;
};

}  // namespace ddmr::hil
