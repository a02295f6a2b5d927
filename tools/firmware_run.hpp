#pragma once
// One HIL run of a firmware, as `ddmr-hil run` does it, then the run's
// artifacts written atomically to the output folder. What is special about
// the firmware comes from its sketch contract (hil/sketch_contract.hpp,
// docs/contracts.md; the reference sketch's is firmware/ddmr_tracking/hil.yaml):
// the start text and when to send it, when the run is complete, its report,
// its pose and loop globals, its EEPROM log. Without a contract (or without
// its `complete` section) the run lasts --seconds of simulated time and ends
// with exit_reason time_limit (success); firmware.csv and eeprom_log.csv are
// written only when the contract says what to put in them.
// Both send the --send bytes at their times and end early with every failure
// reason (crash, watchdog, stack overflow, ...).
//
// Outputs in `out_dir`:
//   uart.txt        every byte the firmware sent, verbatim
//   eeprom.bin      the MCU's EEPROM at the end (1024 bytes on the ATmega328P, 4096 on the ATmega2560)
//   truth.csv       the plant's ground truth at 1 kHz of AVR time, and its drive
//   firmware.csv    the firmware's globals once per control-loop iteration
//   eeprom_log.csv  the firmware's EEPROM log, decoded (sample, t_s, x_m, y_m)
//   summary.json    firmware identity, cycle counts, timing, exit reason, the
//                   parsed firmware report, encoder counts and end poses
//   isr.json, isr.md  per-vector interrupt timing; races on ISR-shared variables
//                   (torn reads and writes, stale reads: hil/race_detector.hpp)
// With --trace:
//   trace.csv       the chosen firmware globals per iteration or every N cycles
// With --profile:
//   loop_profile.csv  compute / wait / period of every control-loop iteration
//   profile.json    flat per-function profile (calls, self and inclusive
//                   cycles) for the whole run and the control loop only
//   profile.txt     the same as sorted text tables
//   (--vcd FILE)    a value-change dump for GTKWave at FILE (anywhere, not
//                   only in out_dir): Uno pins 0-3 and 10-13 with the
//                   synthesised serial frames and PWM, one signal per ISR,
//                   the loop-iteration count (hil/vcd_recorder.hpp); kept,
//                   like every artifact, when the firmware fails
//
// With gdb_port, avr-gdb is served on 127.0.0.1 (hil/gdb_server.hpp): the port
// is bound while the inputs are validated, the run waits for gdb before the
// first instruction, and gdb's kill ends the run (kKilledByDebugger) with the
// artifacts written.

#include <cstdint>
#include <array>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/unity_summary.hpp"
#include "hil/avr_core.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/eeprom_write_timing.hpp"
#include "hil/encoder_injector.hpp"
#include "hil/firmware_report.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/session.hpp"
#include "hil/uart_link.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/bridge_driver.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::tools {

struct FirmwareRunOptions {
    std::filesystem::path firmware;       ///< ELF for the board's MCU
    /// The sketch contract (none: a time-limited run of any firmware).
    std::optional<std::filesystem::path> contract;
    int test_case = 1;                    ///< --case: the contract's {case} in its start text
    bool case_given = false;              ///< --case was given (else: the contract's first case)
    double max_sim_seconds = 60.0;        ///< simulated-time limit [s], > 0
    /// Wall-clock limit [s], > 0 (not applied while avr-gdb is attached:
    /// a debugging session may sit at a breakpoint for as long as it likes).
    double max_wall_seconds = 600.0;
    std::filesystem::path out_dir;        ///< created if missing
    /// --ready-symbol: overrides the contract's start.after-return.
    std::string ready_symbol = "delay";
    bool ready_symbol_given = false;
    /// --case or --ready-symbol was given: a contract is required.
    bool reference_protocol_required = false;
    /// Bytes sent to the firmware's RX at an AVR time (--send TEXT@TIME).
    struct Send {
        std::string bytes;
        double at_s = 0.0;  ///< AVR time [s] (cycles at the board's clock)
    };
    std::vector<Send> sends;
    /// --baud: the host's serial adapter runs at this rate (8N1) and decodes
    /// the firmware's frames as a real adapter would (garbage and framing
    /// errors when the rates differ); unset: the host reads the bytes as sent.
    std::optional<uint32_t> baud;
    std::optional<std::filesystem::path> eeprom_preload;  ///< image of the MCU's EEPROM size
    hil::UartTiming uart_timing = hil::UartTiming::kChip;
    std::optional<std::filesystem::path> plant_file;  ///< plant (and board) YAML
    /// The plant already resolved (a file with overrides and a seed: the
    /// Python API); replaces plant_file's. plant_source names it in summary.json.
    std::optional<plant::RobotParams> plant_params;
    std::string plant_source;
    std::optional<std::filesystem::path> board_file;  ///< board YAML (overrides the plant file's)
    std::optional<std::filesystem::path> world_file;  ///< world YAML (docs/world.md); none: the plain floor
    /// --board-name: the board (MCU, clock) of a run without a board file,
    /// wired as the thesis robot; with a board file, its `board:` must agree.
    std::optional<hil::BoardModel> board_name;
    /// What chose board_name, for a board file at odds with it (default
    /// "--board-name KEY"; a PlatformIO environment names itself), and what
    /// to do about it, appended to that message.
    std::string board_name_origin;
    std::string board_name_advice;
    /// --serial-port: the USART the host's adapter is on, by Arduino name
    /// ("Serial", "Serial1".."Serial3" on a Mega); the board must have it.
    std::string serial_port = "Serial";
    plant::DriveMode pwm = plant::DriveMode::switched;
    hil::EepromTimingMode eeprom_timing = hil::EepromTimingMode::kDatasheet;
    /// Plant step [cycles] = max input latency; 0: 62.5 us of the board's clock (1000 cycles at 16 MHz).
    hil::Cycles coupling_step_cycles = 0;
    bool profile = false;                 ///< exact loop cycle counts (single-steps: slower)
    std::string loop_mark = "delay";      ///< the function each loop iteration calls once
    bool loop_mark_given = false;         ///< --loop-mark given (else: delay for the reference, loop() otherwise)
    std::size_t profile_top = 10;         ///< functions in the stdout table with profile, >= 1
    /// Firmware globals for trace.csv: "name" or "name:type" (type: int8 ...
    /// uint32, float; default by size: 1 uint8, 2 int16, 4 float).
    std::vector<std::string> trace;
    hil::Cycles trace_every_cycles = 0;   ///< 0: one trace row per loop iteration
    /// Value-change dump of the run (pins, PWM, ISRs, loop marker), written
    /// atomically; its folder must exist and be writable.
    std::optional<std::filesystem::path> vcd;
    bool progress = false;                ///< one progress line per simulated second on stderr
    /// Notices on stderr (how long a run without a contract lasts); off for
    /// a run beside another that says it (the fast-forward verification's).
    bool notices = true;
    bool echo_simavr_log = false;         ///< print simavr's warnings on stderr
    /// Skip busy-wait passes exactly (hil/fast_forward.hpp); --no-fast-forward: off.
    bool fast_forward = true;
    /// Serve avr-gdb on 127.0.0.1:PORT and wait for it before the first
    /// instruction (hil/gdb_server.hpp); 1..65535.
    std::optional<uint16_t> gdb_port;
    double gdb_attach_timeout_s = 300.0;  ///< [wall s] how long to wait for avr-gdb
    /// --unity: the run is complete when Unity's summary ("N Tests N Failures
    /// N Ignored", then OK or FAIL) has been received (common/unity_summary.hpp),
    /// instead of the contract's `complete`; every byte the host receives is
    /// also written to stdout as it arrives (`pio test`'s test_testing_command).
    bool unity = false;
    /// The optional instruments (ISR monitor, stack guard, race detector);
    /// each left off makes the run faster (`make bench`: hil_bench).
    hil::SessionInstruments instruments{};
    /// Where the ELF came from (a sketch build, a PlatformIO project):
    /// summary.json's `firmware_source`, null when the ELF was given.
    nlohmann::json firmware_source = nullptr;
    /// The contract's start cue and completion act on the run from the start
    /// (`run`); off, they act only once run_to_end() runs (a front end that
    /// drives the session itself first, as the Python API does).
    bool contract_drives = true;
};

enum class RunExit {
    kReportComplete,  ///< the contract's completion (its report, or its text) was received
    kTimeout,         ///< the simulated-time limit came first
    kCrashed,         ///< simavr stopped the CPU (PC past flash, bad access)
    kSleepForever,    ///< SLEEP with interrupts off
    kReportMalformed, ///< the firmware printed something the report parser rejects
    kPlantFailed,     ///< the plant diverged (non-finite state) or overflowed
    kKilledByDebugger,  ///< avr-gdb sent kill (--gdb)
    kWallTimeout,       ///< the wall-clock limit came first (max_wall_seconds)
    kWatchdogReset,     ///< the watchdog reset the AVR
    kSimavrError,       ///< simavr reported an error (an invalid opcode, ...)
    kStackOverflow,     ///< the stack grew into .data/.bss (hil/stack_guard.hpp)
    kTimeLimit,         ///< a run without a contract's `complete` ran its --seconds (success)
    kResetLoop,         ///< restarts from address 0 without a reset, in a loop (hil/reset_monitor.hpp)
    kStopped,           ///< a front end ran the session to its own ends (the Python API's run_for, run_until)
};

/// "TEXT@TIME" (C escapes \r \n \t \\ \xHH in TEXT; TIME with a unit: 2s,
/// 500ms, 250us) -> bytes and AVR time. Throws std::invalid_argument naming it.
FirmwareRunOptions::Send parse_send(const std::string& spec);

const char* to_string(RunExit exit);

struct FirmwareRunResult {
    RunExit exit = RunExit::kTimeout;
    std::string message;          ///< one line for stderr when exit != kReportComplete
    hil::Cycles cycles_total = 0;
    uint32_t clock_hz = 0;  ///< the board's clock: cycles_total / clock_hz = simulated seconds
    std::optional<hil::Cycles> ready_cycle;  ///< when the case byte was sent
    double wall_seconds = 0.0;
    uint64_t uart_bytes = 0;      ///< bytes the firmware sent, all of them in uart.txt
    hil::EepromImage eeprom{};
    bool has_report = false;      ///< the contract names a report format: `report` is parsed
    hil::FirmwareReport report;
    std::array<hil::EncoderChannelStats, 2> encoder{};
    plant::Pose end_pose_truth{};
    std::optional<plant::Pose> end_pose_firmware;  ///< Ex, Ey, Theta as "END" is sent
    uint64_t loop_iterations = 0;
    double mean_loop_period_s = 0.0;  ///< over the traced iterations
    std::size_t eeprom_log_samples = 0;
    std::vector<hil::LoopIteration> loop_profile;  ///< with FirmwareRunOptions::profile
    /// EEPROM writes, and how many of them are recorded (the first
    /// EepromWriteTiming::kMaxRecordedWrites): loop_profile's EEPROM tags
    /// cover the recorded ones.
    uint64_t eeprom_writes = 0;
    std::size_t eeprom_writes_recorded = 0;
    std::string function_profile_top;  ///< with profile: the top-N table for stdout
    std::optional<UnitySummary> unity;  ///< with FirmwareRunOptions::unity, once its summary came
};

struct RunPlan;

/// One run in phases, for a front end that drives it (the Python API):
/// construction validates every input (throws std::runtime_error /
/// std::invalid_argument naming the bad value, before anything is written),
/// builds the Session and opens the streamed outputs in out_dir;
/// run_to_end() boots, sends the contract's start text and runs until the
/// contract completes or a stop ends the run, as `run` does; finish() writes
/// every artifact and returns what happened. Between construction and
/// finish() the front end may run session() itself.
class FirmwareRun {
public:
    explicit FirmwareRun(FirmwareRunOptions options);
    ~FirmwareRun();
    FirmwareRun(const FirmwareRun&) = delete;
    FirmwareRun& operator=(const FirmwareRun&) = delete;

    hil::Session& session();
    const RunPlan& plan() const;
    const FirmwareRunOptions& options() const;
    /// The contract's {case} for its start text, before the run starts.
    /// Throws std::invalid_argument when the contract takes no case or not this one.
    void set_case(int test_case);
    /// The boot, the start text and the run to its end, as `run` does them;
    /// after the boot (once at its end, then every 10 ms of AVR time),
    /// `between` (if any) is called and may throw to stop the run (Ctrl-C
    /// in the Python API).
    hil::SessionStop run_to_end(const std::function<void()>& between = {});
    /// Ends the run (`stop`: how the last run returned), writes the
    /// artifacts, returns the result. Once.
    FirmwareRunResult finish(hil::SessionStop stop);
    bool finished() const;
    /// The loop profiler (FirmwareRunOptions::profile), or nullptr.
    hil::LoopProfiler* loop_profiler();

private:
    struct State;
    std::unique_ptr<State> s_;
};

/// `ddmr-hil run`: FirmwareRun's phases one after the other.
FirmwareRunResult run_firmware(const FirmwareRunOptions& options);

}  // namespace ddmr::tools
