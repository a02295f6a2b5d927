#pragma once
// ApiSession: one HIL session driven step by step, the engine under the
// Python API (tools/python, docs/python.md). It is a FirmwareRun (the run
// `ddmr-hil run` does, with the same checks, observers and artifacts) whose
// artifacts stream into a private staging folder, plus what a test asks of
// a running robot: run for a time, until a serial text or a condition; type
// into the serial port; read pins, PWM duties, globals, the pose, the truth
// so far and the EEPROM; drive an input pin, write a global, hold a
// sensor's reading. save_artifacts() ends the run and copies the artifacts;
// run_contract() runs the sketch contract as `run` does.
//
// Snapshots: every act on the robot (serial bytes, faults, pin drives,
// global writes, held readings) is logged with its cycle. restore() builds
// the session again from reset and replays the log up to the snapshot's
// cycle. The engine is deterministic and stops at exact instruction
// boundaries, so the state (and every artifact) equals the one the snapshot
// was taken in; the cost is the snapshot's AVR time, simulated again.
//
// Every run is chunked (kChunkSeconds of AVR time) and calls the caller's
// `between` hook between chunks (the Python binding checks for Ctrl-C
// there). Errors are exceptions with one line: std::invalid_argument and
// std::runtime_error for bad input (as the CLI's), ApiTimeout for a wait
// that timed out, ApiRunEnded for a run that ended (the firmware failed,
// the time limit) with the run's own one-line reason.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <variant>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"
#include "scenario/fault_steps.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/pin_waveforms.hpp"
#include "plant/diff_drive_kinematics.hpp"

namespace ddmr::tools {

/// A wait whose AVR-time limit came first (Python: ddmr_hil.Timeout).
class ApiTimeout : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// The run ended and cannot go on: the firmware failed, the plant failed,
/// the session's time limit, or finish (Python: ddmr_hil.RunEnded).
class ApiRunEnded : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ApiOptions {
    std::filesystem::path firmware;
    /// An Arduino sketch (x/x.ino, or its folder) to build for the board
    /// (cached, docs/firmware.md) instead of `firmware`; the user's library
    /// folders after the sketch's src/.
    std::optional<std::filesystem::path> sketch;
    std::vector<std::filesystem::path> libraries;
    std::optional<std::filesystem::path> board_file;
    std::optional<std::filesystem::path> plant_file;
    /// Overrides merged into the plant (file or defaults) one after the
    /// other, each as YAML or JSON text: {"motor1": {"resistance_ohm": 6.0}};
    /// empty: none.
    std::vector<std::string> plant_overrides;
    std::optional<std::filesystem::path> world_file;
    /// The sketch contract; unset: the reference firmware's own, else none.
    std::optional<std::filesystem::path> contract;
    /// The encoders' noise seeds (encoder1 = seed, encoder2 = seed + 1), as a
    /// scenario's seed; unset: the plant's own.
    std::optional<uint64_t> seed;
    double max_sim_seconds = 3600.0;  ///< the session's AVR-time limit [s]
    std::optional<uint32_t> baud;     ///< the host's serial adapter (8N1); unset: bytes as sent
    hil::SessionInstruments instruments{};
    /// The loop profiler (exact compute / wait / period per iteration;
    /// single-steps: slower), for loop_profile().
    bool profile = false;
    std::string loop_mark;  ///< the function each iteration calls once; "": as `run` picks it
    /// Skip busy-wait passes exactly (docs/fast-forward.md); false: execute them.
    bool fast_forward = true;
};

/// One act on the robot, at the AVR cycle it happened (ApiSession's log).
struct ApiAction {
    struct SerialWrite {
        std::string bytes;
    };
    struct Fault {
        std::string kind, value;
    };
    struct PinDrive {
        int pin = -1;
        bool level = false;
    };
    struct VarWrite {
        std::string name, type;
        double value = 0.0;
    };
    struct SensorSet {
        std::string part, reading;
        std::optional<double> value;
    };
    struct LoopProfileStart {};
    hil::Cycles at = 0;
    using Act = std::variant<SerialWrite, Fault, PinDrive, VarWrite, SensorSet, LoopProfileStart>;
    Act act;
};

/// A session's state at a cycle, to return to with ApiSession::restore.
struct ApiSnapshot {
    uint64_t session = 0;           ///< the ApiSession that took it (its id)
    hil::Cycles cycle = 0;
    std::vector<ApiAction> log;     ///< every act before `cycle`
    std::size_t read_mark = 0;      ///< serial_read_new()'s mark
};

class ApiSession {
public:
    /// Called between chunks of a run; it may throw to stop the run.
    using Between = std::function<void()>;
    static constexpr double kChunkSeconds = 0.01;

    explicit ApiSession(const ApiOptions& options);
    ~ApiSession();
    ApiSession(const ApiSession&) = delete;
    ApiSession& operator=(const ApiSession&) = delete;

    [[nodiscard]] hil::Cycles cycle();
    [[nodiscard]] double time_s();

    /// Runs `seconds` more of AVR time.
    void run_for(double seconds, const Between& between = {});
    /// Runs until `text` has arrived after what the host had received, or
    /// throws ApiTimeout after `timeout_s` of AVR time.
    void run_until_serial(const std::string& text, double timeout_s, const Between& between = {});
    /// Runs until `condition` holds (checked every millisecond of AVR time),
    /// or throws ApiTimeout after `timeout_s`.
    void run_until(const std::function<bool()>& condition, double timeout_s, const Between& between = {});
    /// The sketch contract's run, as `ddmr-hil run` does it (boot, start text
    /// with `test_case`, until complete), then the artifacts; on a fresh
    /// session only. Returns summary.json's exit_reason.
    /// `between` as for run_for (after the boot: every 10 ms of AVR time).
    std::string run_contract(std::optional<int> test_case, const Between& between = {});

    /// A scenario fault step (docs/scenarios.md, "Faults": inject, stall,
    /// battery, slip, place, push, move-obstacle) with its value as YAML or
    /// JSON text ({"motor": 2, "for": "300ms"}), checked as a scenario's is;
    /// it acts now, and a timed one (for, over) goes on over AVR time.
    void fault(const std::string& kind, const std::string& value);

    /// Types `bytes` into the firmware's serial port now.
    void serial_write(const std::string& bytes);
    /// Drives input pin `pin` to `level` from now on, as a switch or a
    /// signal generator on the pin (hil/pin_driver.hpp). Throws
    /// std::invalid_argument for a pin the board wires (naming the key) or
    /// the host serial port's.
    void pin_drive(int pin, bool level);
    /// Writes global `name` as `type` ("" by its size), as a debugger does.
    /// Throws std::invalid_argument for a value the type cannot hold.
    void var_write(const std::string& name, const std::string& type, double value);
    /// Holds part `part`'s reading from the next plant step on (nullopt:
    /// the world's again); PartSet::set_reading's checks and messages.
    void sensor_set(const std::string& part, const std::string& reading, std::optional<double> value);

    /// isr.json's content so far (the ISR monitor's statistics and the race
    /// detector's findings); throws std::logic_error when the instruments are off.
    [[nodiscard]] std::string isr_stats_json();
    /// Starts the loop profile at the next return of the loop mark (`run`
    /// starts it when it sends the contract's start text).
    void loop_profile_start();
    /// The control loop's iterations so far (ApiOptions::profile).
    [[nodiscard]] const std::vector<hil::LoopIteration>& loop_profile();

    /// The state now, to restore() later; std::logic_error once the run ended.
    [[nodiscard]] ApiSnapshot snapshot();
    /// Back to `snap` (this session's): the session built again and its log
    /// replayed (see the top of this file). The session before stays as it
    /// was when a replay fails or is stopped.
    void restore(const ApiSnapshot& snap, const Between& between = {});
    /// Everything the host received; read_new(): what came since the last call.
    [[nodiscard]] const std::string& serial_text() const;
    std::string serial_read_new();

    /// A board pin by name ("D10", "A0", "13"); throws naming the board's pins.
    [[nodiscard]] int pin_number(const std::string& name);
    /// The pin's level: an output's as the chip drives it (PWM included),
    /// an input's as PINx reads it.
    [[nodiscard]] bool pin_level(int pin);
    /// The pin's PWM duty [0, 1]: an output's mean level over a period (a
    /// static output: 0 or 1); an input: 0.
    [[nodiscard]] double pwm_duty(int pin);
    /// A global by name and type ("uint32", "float", ... or "" by its size).
    [[nodiscard]] double var_read(const std::string& name, const std::string& type);

    [[nodiscard]] plant::Pose pose();
    /// truth.csv's columns and every row so far (row-major).
    [[nodiscard]] const std::vector<std::string>& truth_columns() const;
    [[nodiscard]] const std::vector<double>& truth_rows() const;
    [[nodiscard]] std::vector<uint8_t> eeprom();
    [[nodiscard]] std::vector<std::string> warnings();

    /// Ends the run (once) and copies its artifacts, the files `run` writes,
    /// into `dir` (created if missing); later calls copy them again.
    void save_artifacts(const std::filesystem::path& dir);
    /// The run's exit_reason once it has ended ("" before).
    [[nodiscard]] const std::string& exit_reason() const;

private:
    class Observer;
    struct Live;
    std::unique_ptr<Live> start() const;
    void act(ApiAction::Act act);
    void apply(const ApiAction::Act& act);
    void run_to(hil::Cycles target, const std::function<bool()>& stop_when, const Between& between);
    void check_running() const;
    void end_run(hil::SessionStop stop);
    FirmwareRun& run();

    ApiOptions options_;
    nlohmann::json firmware_source_;  ///< the sketch build's (summary.json's firmware_source), or null
    uint64_t id_;  ///< unique in the process: a snapshot names its session by it, not by address
    std::unique_ptr<Live> live_;
};

}  // namespace ddmr::tools
