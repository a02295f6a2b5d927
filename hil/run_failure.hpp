#pragma once
// RunFailure: why a HIL run segment ended early, as one line, for every front
// end (`ddmr-hil run`'s exit_message, a scenario step's failure). One place
// decides the priority and the wording:
//
//   1. the StackGuard saw SP below the end of .bss   kStackOverflow
//   2. the ResetMonitor saw a loop of unasked restarts kResetLoop
//   3. the plant stopped (diverged, bad input, ...)   kPlantFailed
//   4. how AvrCore::run_until returned:
//        kCrashed        PC past flash, a bad data access
//        kDone           the firmware slept with interrupts off: kSleepForever
//        kWatchdogReset  the watchdog expired with WDE set
//        kSimavrError    simavr logged an error (an invalid opcode, ...)
//
// kReachedCycle and kCondition are not failures here: what they mean (a
// timeout, a complete report, a step's condition) is the caller's to say.
//
//   (RunStop, AvrCore, StackGuard, ResetMonitor, PlantCoupler, Robot) => RunEnd => RunFailure

#include <cstdint>
#include <optional>
#include <string>

#include "hil/atmega328p.hpp"
#include "hil/avr_core.hpp"
#include "hil/reset_monitor.hpp"
#include "hil/stack_guard.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/robot.hpp"

namespace ddmr::hil {

class RobotRig;

enum class FailureKind {
    kStackOverflow,
    kPlantFailed,
    kCrashed,
    kSleepForever,
    kWatchdogReset,
    kSimavrError,
    kResetLoop,
};

/// What the describer reads when a run segment has ended: plain values, so
/// the wording can be checked without a core.
struct RunEnd {
    RunStop stop = RunStop::kReachedCycle;     ///< what AvrCore::run_until returned
    Cycles cycle = 0;                          ///< AvrCore::cycle() then
    uint32_t clock_hz = 0;                     ///< the board's clock, to give `cycle` in simulated seconds
    uint32_t pc = 0;                           ///< program counter, flash byte address
    std::string simavr_error;                  ///< SimavrLog::first_error()
    std::optional<StackOverflow> stack_overflow;
    std::optional<ResetLoop> reset_loop;       ///< the rig's ResetMonitor::loop()
    plant::StepStatus plant_status = plant::StepStatus::ok;
    double plant_failed_at_s = 0.0;  ///< plant time of the failure [s]
    plant::Pose plant_pose{};        ///< the robot's last finite pose
};

/// Reads the RunEnd of `rig` (its core, reset monitor, coupler and robot) and `stack_guard`
/// (nullptr: none watches the stack) after run_until returned `stop`.
RunEnd observe_run_end(RunStop stop, RobotRig& rig, const StackGuard* stack_guard);

/// How the line is worded. kStandalone (`ddmr-hil run`, README's exit-reason
/// table): names the firmware and gives the simulated time. kInStep (a
/// scenario step, whose failure line already gives the time): shorter.
enum class FailureWording { kStandalone, kInStep };

struct RunFailure {
    FailureKind kind = FailureKind::kCrashed;
    std::string message;  ///< one line, no trailing newline
};

/// The failure that ended the segment, by the priority above; std::nullopt
/// if there is none (the stop was kReachedCycle or kCondition, with the stack
/// and the plant fine).
std::optional<RunFailure> describe_run_failure(const RunEnd& end, FailureWording wording);

}  // namespace ddmr::hil
