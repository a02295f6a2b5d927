#pragma once
// A scenario: one firmware regression test in AVR time (issue 7), as plain
// data. Loaded and validated by scenario_yaml.hpp, run by scenario_runner.hpp.
// The file format, every key, unit and default: docs/scenarios.md.
//
// Times are AVR cycles at the Uno's 16 MHz; lengths in m, angles in rad.
// Paths are absolute (resolved against the scenario's folder at load time).

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "common/sketch_build.hpp"
#include "hil/cycle_time.hpp"
#include "hil/eeprom_write_timing.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/board.hpp"
#include "plant/bridge_driver.hpp"
#include "plant/robot_params.hpp"
#include "plant/world.hpp"

namespace ddmr::hil {
struct TruthSample;
}

namespace ddmr::tools::scenario {

using hil::Cycles;

// --- Wokwi-compatible steps -------------------------------------------------
struct Delay {  ///< `delay: 500ms`: let the AVR run
    Cycles duration = 0;
};
struct WriteSerial {  ///< `write-serial: "1"`: bytes into the firmware's RX, at the adapter's baud
    std::string text;
};
struct WaitSerial {  ///< `wait-serial: "END"`: run until the text is received (after the last match)
    std::string text;
    Cycles timeout = 0;  ///< 0: none of its own (the scenario's timeout ends it: verdict firmware)
};
struct ExpectSerial {  ///< `expect-serial: regex`: the text received so far matches (ECMAScript search)
    std::string pattern;
};
struct FailSerial {  ///< `fail-serial: regex`: from now on, any received line matching fails the scenario
    std::string pattern;
};
struct WaitPin {  ///< `wait-pin: {pin: 12, value: 1, timeout: 1s}`
    int pin = 0;
    bool value = false;
    Cycles timeout = 0;  ///< 0: none of its own (as WaitSerial)
};
struct ExpectPin {  ///< `expect-pin: {pin: 13, value: 1}`: the digital level now
    int pin = 0;
    bool value = false;
};
struct ExpectPart {  ///< `expect-part: {part: shield, port: Q2, value: 1}`: a part's output level now
    std::string part;
    std::string port;
    bool value = false;
};
struct ExpectWarning {  ///< `expect-warning: regex`: a wiring warning so far matches (a driver input never made an output)
    std::string pattern;
};
struct ExpectPwm {  ///< `expect-pwm: {pin: 10, duty: 0.4, tol: 0.02}`: the timer's duty now
    int pin = 0;
    double duty = 0.0;
    double tol = 0.0;
};

// --- robot and firmware checks ---------------------------------------------
enum class CompareOp { kEq, kNe, kLt, kLe, kGt, kGe };
const char* to_string(CompareOp op);
bool holds(double lhs, CompareOp op, double rhs);

struct ExpectVar {  ///< `expect-var: {name: Count1, op: ">=", value: 7000}`
    std::string name;
    std::optional<hil::VarType> type;  ///< default by the symbol's size (1 uint8, 2 int16, 4 float)
    CompareOp op = CompareOp::kEq;
    double value = 0.0;
};
enum class PoseSource { kTruth, kFirmware };
struct ExpectPose {  ///< `expect-pose: {source: truth, x_m: .., y_m: .., tol_m: ..}`
    PoseSource source = PoseSource::kTruth;
    double x_m = 0.0, y_m = 0.0;
    double tol_m = 0.0;
    std::optional<double> theta_rad;
    double tol_rad = 0.0;
};
struct ExpectEeprom {  ///< raw bytes (`bin`) or the decoded log against a CSV (`log`, `tol_m`)
    std::optional<std::filesystem::path> bin;
    std::optional<std::filesystem::path> log;
    double tol_m = 0.0;
};
struct ExpectCompare {  ///< the EEPROM log against the host simulation of `case`
    int test_case = 1;
    double max_rms_m = 0.0;
    std::optional<double> max_endpoint_m;
};
/// A bound on a measured value: `value` (an upper bound) or `[min, max]`.
struct Range {
    std::optional<double> min, max;
    bool set() const { return min || max; }
    bool contains(double v) const { return (!min || v >= *min) && (!max || v <= *max); }
};
struct ExpectLoop {  ///< control-loop timing in us (turns on the exact loop profiler)
    Range max_us, p99_us, mean_us;                      ///< compute part (top of the iteration to delay())
    Range period_max_us, period_p99_us, period_mean_us;  ///< whole period
    bool include_eeprom_writes = true;  ///< false: only iterations without an EEPROM write
};
struct ExpectIsr {  ///< `expect-isr: {vector: INT0, max_latency_cycles: 200}`
    std::string vector;
    std::optional<Cycles> max_latency_cycles, max_duration_cycles;
    std::optional<uint64_t> min_count;
};
/// No access of the main program to an ISR-shared variable (the named ones,
/// or every one) was torn with a value observed that should never be seen
/// (hil/race_detector.hpp): `- expect-no-torn-reads` or
/// `- expect-no-torn-reads: [Count1, Count2]`.
struct ExpectNoTornReads {
    std::vector<std::string> variables;  ///< empty: every variable
};

// --- plant signals (the robot's ground truth now) ---------------------------
/// The names a scenario can check: every truth.csv column but t_s (x_m, ...,
/// dir2) and the wheel aliases (left.wheel_rad_s, ...; right = motor 1,
/// left = motor 2). In docs/scenarios.md order.
const std::vector<std::string>& plant_signal_names();
bool is_plant_signal(std::string_view name);
/// The signal's value in `t` (as truth.csv writes it; dir as 1/0). Throws
/// std::invalid_argument for an unknown name.
double plant_signal(const hil::TruthSample& t, std::string_view name);
/// The world's signals (hil/world_truth.hpp): line_offset_m, wall_distance_m,
/// contact, contacts.
const std::vector<std::string>& world_signal_names();

struct WaitUntil {  ///< `wait-until: {signal: x_m, op: ">=", value: 0.1, timeout: 7s}`
    std::string signal;
    CompareOp op = CompareOp::kEq;
    double value = 0.0;
    Cycles timeout = 0;  ///< 0: none of its own (as WaitSerial)
};
struct ExpectSignal {  ///< `expect: {signal, op, value}` or `expect: {signal, between: [a, b]}`
    std::string signal;
    CompareOp op = CompareOp::kEq;
    double value = 0.0;
    Range between;  ///< set: a <= signal <= b (instead of op and value)
};
/// `measure: {signal: line_offset_m}`: from now on, each truth sample (1 ms)
/// of the signal goes into its statistics, for expect-stats.
struct Measure {
    std::string signal;
};
/// `expect-stats: {signal, rms_max, abs_max, mean, min_samples}`: the
/// statistics of the signal's samples since its measure step.
struct ExpectStats {
    std::string signal;
    std::optional<double> rms_max;  ///< sqrt(mean of squares) at most this
    std::optional<double> abs_max;  ///< every |sample| at most this
    Range mean;                     ///< the mean within [min, max]
    Range range;                    ///< every sample within [min, max]
    uint64_t min_samples = 1;       ///< at least this many samples
};
struct ExpectEncoders {  ///< `expect-encoders: {max_lost: 0}`: edges lost at the pins
    uint64_t max_lost = 0;
};

// --- faults (at the step's time; `for:` ends them) --------------------------
// Wheel numbers: 1 = right = motor 1, 2 = left = motor 2 (hil::wheel_name);
// the files may give either.
struct InjectDrop {  ///< `inject: {encoder: 1, drop: 0.05}`: seeded missed edges
    int encoder = 1;
    double drop = 0.0;
    std::optional<Cycles> duration;
};
struct Stall {  ///< `stall: {motor: 2, for: 300ms}`: the shaft is held
    int motor = 1;
    Cycles duration = 0;
};
struct Battery {  ///< `battery: {volts: 5.2}`: an ideal source from now on
    double volts = 0.0;
    std::optional<Cycles> duration;
};
struct Slip {  ///< `slip: {wheel: 1, traction: 0.3, for: 500ms}`
    int wheel = 1;
    double traction = 1.0;
    std::optional<Cycles> duration;
};
struct Push {  ///< `push: {dx_m: 0.05, dy_m: 0, dtheta_rad: 0, over: 200ms}`: the robot is displaced
    double dx_m = 0.0, dy_m = 0.0, dtheta_rad = 0.0;
    Cycles over = 0;  ///< spread evenly over this time (a hand turning it); 0: at once
};
/// `place: {x_m, y_m, heading_deg}`: the robot is set down at this pose (a
/// hand lifting it; the wheels keep turning as they were, odometry does not see it).
struct Place {
    double x_m = 0.0, y_m = 0.0, heading_deg = 0.0;
};
/// `move-obstacle: {name: box, dx_m: 0.2, dy_m: 0, over: 1s}`: a named
/// obstacle of the world moves (at once, or evenly over `over`).
struct MoveObstacle {
    std::string name;
    double dx_m = 0.0, dy_m = 0.0;
    Cycles over = 0;
};
struct Reset {};  ///< AVR reset (the EEPROM and the robot keep their state)

using StepAction = std::variant<Delay, WriteSerial, WaitSerial, ExpectSerial, FailSerial, WaitPin, ExpectPin,
                                ExpectPart, ExpectWarning, ExpectPwm, ExpectVar, ExpectPose, ExpectEeprom, ExpectCompare, ExpectLoop,
                                ExpectIsr, ExpectNoTornReads, ExpectEncoders, WaitUntil, ExpectSignal, Measure, ExpectStats, InjectDrop,
                                Stall, Battery, Slip, Push, Place, MoveObstacle, Reset>;

struct Step {
    int line = 0;        ///< 1-based line in the scenario file
    std::string kind;    ///< the step's key, e.g. "wait-serial"
    std::string text;    ///< the step as written, for messages
    StepAction action;
};

struct Scenario {
    std::filesystem::path file;
    std::string name;                    ///< default: the file's stem
    std::string description;
    std::filesystem::path firmware;      ///< ELF (empty until the sketch is built, if one is named)
    /// `firmware: {sketch: x/x.ino}`: built by common/sketch_build.hpp before the run.
    std::optional<std::filesystem::path> sketch;
    /// `libraries: [DIR, ...]` (relative to the scenario file): the sketch's
    /// library folders, before the sketchbook's (common/arduino_libraries.hpp).
    std::vector<std::filesystem::path> libraries;
    /// The sketch's build (what arduino-builder used), once built: result.json's `sketch`.
    std::optional<SketchBuild> sketch_build;
    /// `firmware: {platformio: DIR, env: NAME}`: result.json's `platformio` (null otherwise).
    nlohmann::json firmware_source = nullptr;
    plant::RobotParams plant = plant::default_robot_params();  ///< file + overrides + seed
    std::optional<std::filesystem::path> plant_file;
    hil::BoardWiring board = hil::default_board();        ///< `board:` file, else the thesis robot
    std::optional<std::filesystem::path> board_file;
    plant::World world{};                              ///< `world:` file, else the plain floor
    std::optional<std::filesystem::path> world_file;
    plant::DriveMode pwm = plant::DriveMode::switched;
    hil::EepromTimingMode eeprom_timing = hil::EepromTimingMode::kDatasheet;
    uint64_t seed = 1;
    /// `fast-forward: false` (or `scenario --no-fast-forward`): execute every
    /// pass of busy-wait loops instead of skipping them exactly (docs/fast-forward.md).
    bool fast_forward = true;
    Cycles timeout = 0;                  ///< simulated-time limit of the whole scenario
    uint32_t baud = 9600;                ///< the host's serial adapter
    int serial_usart = 0;                ///< `serial: {port: Serial1}`: the USART the adapter is on
    std::optional<std::filesystem::path> eeprom_preload;
    std::vector<Step> steps;
    /// True if a step needs the exact loop profiler (expect-loop): the run
    /// then single-steps and is about 3x slower.
    bool needs_loop_profile() const;
};

}  // namespace ddmr::tools::scenario
