// RunFailure: the one-line reasons `ddmr-hil run` (kStandalone) and a
// scenario step (kInStep) give, word for word, and which one wins when
// several hold at once.
#include "hil/run_failure.hpp"

#include <gtest/gtest.h>

namespace ddmr::test {
namespace {

using hil::FailureKind;
using hil::FailureWording;
using hil::RunEnd;
using hil::RunStop;

/// A segment that stopped at cycle 160,000 (10 ms at 16 MHz), PC 0x01a2.
RunEnd stopped(RunStop stop) {
    RunEnd end;
    end.stop = stop;
    end.cycle = 160'000;
    end.clock_hz = 16'000'000;
    end.pc = 0x01a2;
    return end;
}

std::string message(const RunEnd& end, FailureWording wording) {
    const auto f = hil::describe_run_failure(end, wording);
    return f ? f->message : "(none)";
}

TEST(RunFailure, ReachedCycleAndConditionAreNotFailures) {
    for (const auto w : {FailureWording::kStandalone, FailureWording::kInStep}) {
        EXPECT_FALSE(hil::describe_run_failure(stopped(RunStop::kReachedCycle), w));
        EXPECT_FALSE(hil::describe_run_failure(stopped(RunStop::kCondition), w));
    }
}

TEST(RunFailure, EachStopInBothWordings) {
    const auto crash = stopped(RunStop::kCrashed);
    EXPECT_EQ(hil::describe_run_failure(crash, FailureWording::kInStep)->kind, FailureKind::kCrashed);
    EXPECT_EQ(message(crash, FailureWording::kStandalone),
              "firmware crashed at PC 0x01a2, cycle 160000 (t = 0.010000 s)");
    EXPECT_EQ(message(crash, FailureWording::kInStep), "crashed at PC 0x01a2, cycle 160000");

    const auto sleep = stopped(RunStop::kDone);
    EXPECT_EQ(hil::describe_run_failure(sleep, FailureWording::kInStep)->kind, FailureKind::kSleepForever);
    EXPECT_EQ(message(sleep, FailureWording::kStandalone),
              "firmware went to sleep with interrupts off at PC 0x01a2, cycle 160000");
    EXPECT_EQ(message(sleep, FailureWording::kInStep),
              "the firmware slept with interrupts off at PC 0x01a2, cycle 160000");

    const auto watchdog = stopped(RunStop::kWatchdogReset);
    EXPECT_EQ(hil::describe_run_failure(watchdog, FailureWording::kInStep)->kind, FailureKind::kWatchdogReset);
    EXPECT_EQ(message(watchdog, FailureWording::kStandalone), "watchdog reset at cycle 160000 (t = 0.010000 s)");
    EXPECT_EQ(message(watchdog, FailureWording::kInStep), "watchdog reset at cycle 160000");

    auto simavr = stopped(RunStop::kSimavrError);
    simavr.simavr_error = "CORE: *** 01a0: Invalid Opcode SP=08fd O=0001";
    EXPECT_EQ(hil::describe_run_failure(simavr, FailureWording::kInStep)->kind, FailureKind::kSimavrError);
    for (const auto w : {FailureWording::kStandalone, FailureWording::kInStep}) {
        EXPECT_EQ(message(simavr, w),
                  "simavr error at PC 0x01a2, cycle 160000: CORE: *** 01a0: Invalid Opcode SP=08fd O=0001");
    }
}

TEST(RunFailure, StackOverflowThenPlantBeforeTheStop) {
    // The guard's sample may lead to a crash in the same batch: the overflow
    // is the cause and is reported; then a plant failure; then the stop.
    auto end = stopped(RunStop::kCrashed);
    end.plant_status = plant::StepStatus::diverged;
    end.plant_failed_at_s = 0.0095;
    end.plant_pose = plant::Pose{0.25, -1.5e-3, 0.0};
    end.stack_overflow = hil::StackOverflow{159'744, 0x0103, 0x014c};
    for (const auto w : {FailureWording::kStandalone, FailureWording::kInStep}) {
        const auto f = hil::describe_run_failure(end, w);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->kind, FailureKind::kStackOverflow);
        EXPECT_EQ(f->message, "stack overflow into .bss at cycle 159744 (SP 0x0103 below the end of .bss 0x014c)");
    }
    end.stack_overflow.reset();
    for (const auto w : {FailureWording::kStandalone, FailureWording::kInStep}) {
        const auto f = hil::describe_run_failure(end, w);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->kind, FailureKind::kPlantFailed);
        EXPECT_EQ(f->message, "plant diverged at t=0.009500 s (last finite pose x=0.25 m, y=-0.0015 m)");
    }
    // A plant failure also ends a segment that stopped normally.
    end.stop = RunStop::kCondition;
    EXPECT_EQ(hil::describe_run_failure(end, FailureWording::kInStep)->kind, FailureKind::kPlantFailed);
}

TEST(RunFailure, AResetLoopAfterAStackOverflowBeforeThePlant) {
    // The ResetMonitor stops the run (kCondition) at the 11th restart within a second.
    auto end = stopped(RunStop::kCondition);
    end.plant_status = plant::StepStatus::diverged;
    end.reset_loop = hil::ResetLoop{17'802, 11, "`call 0` at PC 0x02ea in watch(unsigned char)"};
    for (const auto w : {FailureWording::kStandalone, FailureWording::kInStep}) {
        const auto f = hil::describe_run_failure(end, w);
        ASSERT_TRUE(f);
        EXPECT_EQ(f->kind, FailureKind::kResetLoop);
        EXPECT_EQ(f->message,
                  "reset loop: the firmware restarted from address 0 without a reset more than 10 times within a "
                  "simulated second (11 in all by cycle 17802, t = 0.001113 s); the first came from `call 0` at PC "
                  "0x02ea in watch(unsigned char)");
    }
    end.stack_overflow = hil::StackOverflow{159'744, 0x0103, 0x014c};
    EXPECT_EQ(hil::describe_run_failure(end, FailureWording::kStandalone)->kind, FailureKind::kStackOverflow);
}

}  // namespace
}  // namespace ddmr::test
