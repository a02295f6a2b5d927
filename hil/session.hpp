#pragma once
// Session: one simulated robot, the engine every front end drives (`run`,
// `profile`, `scenario`, `calibrate`'s HIL confirmation).
//
// It is built from a firmware (a validated ElfImage), a rig configuration
// (board, plant, coupler, timing) and SessionOptions, and owns:
//   - the RobotRig (AvrCore, UART, EEPROM, driver reader, plant, coupler,
//     encoders, firmware variables);
//   - the built-in instruments the options ask for: the ISR monitor, the
//     stack guard, the race detector, the host's serial adapter, the gdb
//     server;
//   - the observers the front end attaches (SessionObserver): what the host
//     receives, each coupling boundary;
//   - the one stepping loop (run()): to a cycle or until a condition, with
//     timed actions (at(), post()) and the stop conditions every run has: a
//     firmware failure (hil/run_failure.hpp), the time limit, the wall-clock
//     limit, the debugger's kill, and the front end's own end (end_run(),
//     end_after());
//   - the end of a run, described in one place (failure(), end_message()).
//
// Sessions are independent: no state is shared between two of them, so
// several can run in one process, one per thread (simavr's logger is routed
// per avr_t: hil/simavr_log.hpp).
//
//   ElfImage + RigConfig + SessionOptions => Session => run() => SessionStop

#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "hil/cycle_time.hpp"
#include "hil/elf_image.hpp"
#include "hil/gdb_server.hpp"
#include "hil/host_adapter.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/race_detector.hpp"
#include "hil/robot_rig.hpp"
#include "hil/run_failure.hpp"
#include "hil/stack_guard.hpp"

namespace ddmr::hil {

class Session;

/// What a front end (or an instrument) sees of a running session. Called
/// inside the simulation: keep the calls short and do not throw; to act on
/// the simulation, post() an action or end_run().
class SessionObserver {
public:
    virtual ~SessionObserver() = default;
    /// Every byte the host receives, in order (as the adapter decodes it,
    /// or as the firmware sent it without one), at `cycle`.
    virtual void on_host_byte(char /*c*/, Cycles /*cycle*/) {}
    /// Every coupling boundary, after the plant was stepped over the next
    /// interval and the host's settled bytes were delivered.
    virtual void on_boundary(Cycles /*cycle*/) {}
    /// Every ground-truth sample of the plant (truth.csv's rows).
    virtual void on_truth(const TruthSample& /*sample*/) {}
};

/// Which instruments a session builds. The defaults are every front end's
/// today; each can be left off (the run is then faster, bench: hil_bench).
struct SessionInstruments {
    bool isr_monitor = true;    ///< per-vector interrupt timing (hil/isr_monitor.hpp)
    bool stack_guard = true;    ///< SP below .bss ends the run (hil/stack_guard.hpp)
    bool race_detector = true;  ///< torn and stale accesses (hil/race_detector.hpp)
};

struct SessionOptions {
    SessionInstruments instruments{};
    /// The host's serial adapter at this rate (8N1, hil/host_adapter.hpp);
    /// unset: the host reads the bytes as the firmware sends them.
    std::optional<uint32_t> adapter_baud;
    std::optional<EepromImage> eeprom_preload;  ///< the MCU's whole EEPROM
    Cycles time_limit = 0;                      ///< simulated-time limit [cycles], > 0
    /// Wall-clock limit [s], checked every simulated second; 0: none. Not
    /// applied while avr-gdb serves the run.
    double wall_limit_s = 0.0;
    std::optional<GdbServerConfig> gdb;  ///< serve avr-gdb (bound at construction)
    bool echo_simavr_log = false;        ///< simavr's own messages on stderr
    /// Skip whole passes of busy-wait loops exactly (hil/fast_forward.hpp);
    /// never while avr-gdb serves the run.
    bool fast_forward = true;
    /// Called about once per simulated second while run() runs (progress lines).
    std::function<void(Cycles)> on_progress;
};

/// Why run() returned.
enum class SessionStop {
    kReachedCycle,  ///< the target cycle was reached
    kCondition,     ///< the caller's condition held
    kEnded,         ///< the front end ended the run (end_run, end_after)
    kTimeLimit,     ///< the session's simulated-time limit was reached
    kWallLimit,     ///< the wall-clock limit came first
    kKilled,        ///< avr-gdb sent kill
    kFailure,       ///< the firmware or the plant failed: failure() says how
};

const char* to_string(SessionStop stop);

/// What run() runs to, besides its target cycle.
struct RunCondition {
    /// Checked each time the loop regains control (after any stop request,
    /// at a timed action); run() returns kCondition when it holds.
    std::function<bool()> met;
    /// Also checked at every coupling boundary (a plant signal, a pin).
    bool poll_each_boundary = false;
};

class Session {
public:
    /// run()'s target when only a condition or an end stops it.
    static constexpr Cycles kNoTarget = ~Cycles{0};

    /// Builds the rig and the instruments (throws std::invalid_argument /
    /// std::runtime_error naming a bad value); with options.gdb, binds the
    /// port (a port in use is refused here, before anything is written).
    Session(const ElfImage& elf, const RigConfig& config, SessionOptions options);
    ~Session();
    Session(const Session&) = delete;
    Session& operator=(const Session&) = delete;

    RobotRig& rig() { return *rig_; }
    AvrCore& core() { return rig_->core(); }
    const ElfImage& elf() const { return elf_; }
    const SessionOptions& options() const { return options_; }
    double seconds(Cycles c) const { return cycles_to_s(c, clock_hz_); }
    Cycles cycle() const { return rig_->core().cycle(); }

    // --- instruments (nullptr when left off) ------------------------------
    IsrMonitor* isr_monitor() { return isr_ ? isr_.get() : nullptr; }
    const StackGuard* stack_guard() const { return stack_guard_ ? stack_guard_.get() : nullptr; }
    RaceDetector* race_detector() { return races_ ? races_.get() : nullptr; }
    HostAdapter* adapter() { return adapter_ ? adapter_.get() : nullptr; }
    GdbServer* gdb() { return gdb_ ? gdb_.get() : nullptr; }
    /// Waits for avr-gdb to attach (with options.gdb); the wall clock restarts.
    void wait_for_debugger();
    /// Wall-clock seconds since the session was built (or gdb attached).
    double wall_seconds() const;
    /// Replaces options().on_progress.
    void set_progress(std::function<void(Cycles)> on_progress) { options_.on_progress = std::move(on_progress); }

    /// Adds an observer, called in the order added; it must outlive the
    /// session's runs (the session does not own it).
    void attach(SessionObserver& observer) { observers_.push_back(&observer); }

    // --- the host's side of the serial line --------------------------------
    /// Types `text` into the firmware's serial port now (as the adapter's
    /// frames reach the firmware at its baud rate, when there is an adapter);
    /// returns the bytes the firmware receives.
    std::string send(const std::string& text);
    /// Delivers the bytes still on the wire to the observers (the run's end).
    void flush_host_bytes();

    // --- actions and ends ---------------------------------------------------
    /// Runs `action` once the AVR reaches `cycle` (between instructions;
    /// actions due together run in the order added).
    void at(Cycles cycle, std::function<void()> action);
    /// Calls `sample` every `period` cycles from now (a cycle timer: the run
    /// stays batched), for as long as the session lives.
    void every(Cycles period, std::function<void(Cycles)> sample);
    /// Runs `action` as soon as the running instruction batch ends.
    void post(std::function<void()> action);
    /// Makes run() look at its condition as soon as the running batch ends.
    void interrupt() { rig_->core().request_stop(); }
    /// Ends the run as soon as the running batch ends: run() returns kEnded.
    void end_run();
    /// Ends the run `delay` cycles from now (e.g. once the last byte has left
    /// the wire), or at the next stop before that.
    void end_after(Cycles delay);
    bool ended() const { return end_requested_; }

    // --- the loop -----------------------------------------------------------
    /// Runs until `target`, the condition, or a stop that ends the run.
    SessionStop run(Cycles target, const RunCondition& until = {});
    /// Runs the boot: until the firmware first returns from `function`
    /// (kCondition), or a stop that ends the run (kReachedCycle at the time limit).
    SessionStop run_to_first_return_from(const ElfSymbol& function);

    /// How failure() is worded: kStandalone (`run`, the default), kInStep (a scenario step).
    void set_failure_wording(FailureWording wording) { wording_ = wording; }
    /// The failure that ended the run (after kFailure): kind and one line.
    const std::optional<RunFailure>& failure() const { return failure_; }
    /// The one line for a stop that ended the run: kWallLimit, kKilled,
    /// kFailure (in the failure wording); empty for the others (theirs to word).
    std::string end_message(SessionStop stop) const;

private:
    SessionStop classify(RunStop stop);
    void run_due_actions();
    void deliver(const std::vector<LineByte>& bytes);
    void on_boundary(Cycles cycle);
    static uint64_t on_wall_check(struct avr_t* avr, uint64_t when, void* param);
    static uint64_t on_periodic(struct avr_t* avr, uint64_t when, void* param);
    struct Periodic {
        std::function<void(Cycles)> sample;
        Cycles period = 0;
    };

    const ElfImage& elf_;
    SessionOptions options_;
    std::unique_ptr<RobotRig> rig_;
    uint32_t clock_hz_ = 0;
    std::unique_ptr<IsrMonitor> isr_;
    std::unique_ptr<StackGuard> stack_guard_;
    std::unique_ptr<RaceDetector> races_;
    std::unique_ptr<HostAdapter> adapter_;
    std::unique_ptr<GdbServer> gdb_;
    std::vector<SessionObserver*> observers_;
    std::vector<std::unique_ptr<Periodic>> periodic_;
    std::vector<LineByte> scratch_;
    std::vector<std::pair<Cycles, std::function<void()>>> timed_;
    const RunCondition* until_ = nullptr;  ///< the running run()'s condition
    bool end_requested_ = false;  ///< end_run or end_after: the next stop ends the run
    bool end_now_ = false;        ///< the run has ended
    std::optional<RunFailure> failure_;
    FailureWording wording_ = FailureWording::kStandalone;
    std::chrono::steady_clock::time_point wall_start_;
    bool wall_tripped_ = false;
    Cycles wall_period_ = 0;
    Cycles next_progress_ = 0;
};

}  // namespace ddmr::hil
