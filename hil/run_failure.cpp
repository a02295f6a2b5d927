#include "hil/run_failure.hpp"

#include <fmt/format.h>

#include "hil/cycle_time.hpp"
#include "hil/robot_rig.hpp"

namespace ddmr::hil {

RunEnd observe_run_end(RunStop stop, RobotRig& rig, const StackGuard* stack_guard) {
    AvrCore& core = rig.core();
    RunEnd end;
    end.stop = stop;
    end.cycle = core.cycle();
    end.clock_hz = core.clock_hz();
    end.pc = core.pc();
    end.simavr_error = core.log().first_error();
    if (stack_guard != nullptr) end.stack_overflow = stack_guard->overflow();
    end.reset_loop = rig.reset_monitor().loop();
    end.plant_status = rig.coupler().status();
    end.plant_failed_at_s = rig.coupler().failed_at_s();
    end.plant_pose = rig.robot().pose();
    return end;
}

std::optional<RunFailure> describe_run_failure(const RunEnd& end, FailureWording wording) {
    const bool standalone = wording == FailureWording::kStandalone;
    const double t_s = cycles_to_s(end.cycle, end.clock_hz);
    if (end.stack_overflow) {
        const StackOverflow& o = *end.stack_overflow;
        return RunFailure{FailureKind::kStackOverflow,
                          fmt::format("stack overflow into .bss at cycle {} (SP 0x{:04x} below the end of .bss 0x{:04x})",
                                      o.cycle, o.sp, o.bss_end)};
    }
    if (end.reset_loop) {
        const ResetLoop& l = *end.reset_loop;
        return RunFailure{FailureKind::kResetLoop,
                          fmt::format("reset loop: the firmware restarted from address 0 without a reset more than "
                                      "{} times within a simulated second ({} in all by cycle {}, t = {:.6f} s); the "
                                      "first came from {}",
                                      ResetRate::kMaxPerWindow, l.count, l.cycle, cycles_to_s(l.cycle, end.clock_hz),
                                      l.first_from)};
    }
    if (end.plant_status != plant::StepStatus::ok) {
        return RunFailure{FailureKind::kPlantFailed,
                          fmt::format("plant {} at t={:.6f} s (last finite pose x={:.6g} m, y={:.6g} m)",
                                      plant::to_string(end.plant_status), end.plant_failed_at_s, end.plant_pose.x_m,
                                      end.plant_pose.y_m)};
    }
    switch (end.stop) {
        case RunStop::kCrashed:
            return RunFailure{FailureKind::kCrashed,
                              standalone ? fmt::format("firmware crashed at PC 0x{:04x}, cycle {} (t = {:.6f} s)",
                                                       end.pc, end.cycle, t_s)
                                         : fmt::format("crashed at PC 0x{:04x}, cycle {}", end.pc, end.cycle)};
        case RunStop::kDone:
            return RunFailure{
                FailureKind::kSleepForever,
                fmt::format("{} with interrupts off at PC 0x{:04x}, cycle {}",
                            standalone ? "firmware went to sleep" : "the firmware slept", end.pc, end.cycle)};
        case RunStop::kWatchdogReset:
            return RunFailure{FailureKind::kWatchdogReset,
                              standalone ? fmt::format("watchdog reset at cycle {} (t = {:.6f} s)", end.cycle, t_s)
                                         : fmt::format("watchdog reset at cycle {}", end.cycle)};
        case RunStop::kSimavrError:
            return RunFailure{FailureKind::kSimavrError, fmt::format("simavr error at PC 0x{:04x}, cycle {}: {}", end.pc,
                                                                     end.cycle, end.simavr_error)};
        case RunStop::kReachedCycle:
        case RunStop::kCondition:
            break;
    }
    return std::nullopt;
}

}  // namespace ddmr::hil
