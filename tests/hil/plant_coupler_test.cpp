// PlantCoupler, closed loop: the unmodified firmware steers the plant and
// reads its encoders. Behaviour the real robot shows, and the coupling's
// own guarantees (latency, wiring that matters).
#include "hil/plant_coupler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "support/rig_run.hpp"

namespace ddmr::test {
namespace {

constexpr double kTwoPi = 6.283185307179586;

double distance_to_circle(const plant::Pose& p, double radius) {
    return std::abs(std::hypot(p.x_m, p.y_m) - radius);
}

/// A motor that turned at least this much [rad]: 100 turns, 800 encoder
/// edges. In case 1 each motor turns 700-950 times; a motor that never
/// starts turns 0.
constexpr double kTurnedRad = 100 * kTwoPi;

/// The firmware ran its case to the end (its report is complete) and the
/// robot drove: it got 0.1 m (a sixth of the circle's radius) from its start
/// and both motors turned. A robot that never moved also ends 0.6 m from the
/// circle (it starts at the centre), so a check that it missed the circle
/// says nothing without this.
void expect_completed_and_moved(const RigRun& run) {
    EXPECT_TRUE(run.report_complete) << run.text.substr(0, 200);
    EXPECT_GT(run.farthest_m, 0.1);
    EXPECT_GT(std::abs(run.motor_angle_rad[0]), kTurnedRad);
    EXPECT_GT(std::abs(run.motor_angle_rad[1]), kTurnedRad);
}

/// ISRs of a channel that started at or before `cycle`.
std::size_t isr_count_by(const std::vector<hil::Cycles>& entries, hil::Cycles cycle) {
    return static_cast<std::size_t>(std::upper_bound(entries.begin(), entries.end(), cycle) - entries.begin());
}

const RigRun& case1() {
    static const RigRun run = run_rig_case('1');
    return run;
}

TEST(PlantCoupler, Case1DrivesOnceAroundAndEndsNearTheGoalCircle) {
    const auto& run = case1();
    ASSERT_TRUE(run.report_complete) << run.text.substr(0, 200);
    // The goal runs once around the 0.6 m circle centred on the start point
    // in 12 s; the robot follows it once around: heading > 2 pi at the end.
    EXPECT_GT(run.end_truth.theta_rad, kTwoPi);
    // Bound: 0.1 m from the circle. The firmware believes Ka = 0.0054 and its
    // gains truncate (kx = 1); its dead-reckoning drifts from the truth (the
    // plant's K_a is 0.00384, wheels r = 0.0322 m vs its 0.03215 m): the thesis
    // robot ended 3.7 % off, ours about 10 % (0.064 m with the defaults).
    EXPECT_LT(distance_to_circle(run.end_truth, 0.6), 0.10);
}

TEST(PlantCoupler, Case2RunsToEndAndFollowsItsCircle) {
    const auto run = run_rig_case('2');
    ASSERT_TRUE(run.report_complete);
    EXPECT_EQ(run.report.banner, "0.4m");
    EXPECT_GT(run.end_truth.theta_rad, kTwoPi);
    EXPECT_LT(distance_to_circle(run.end_truth, 0.4), 0.10);
}

TEST(PlantCoupler, FirmwareCountsEveryEncoderEdgeTheHilInjects) {
    const auto& run = case1();
    ASSERT_TRUE(run.report_complete);
    for (unsigned ch = 0; ch < 2; ++ch) {
        const auto& s = run.encoder[ch];
        EXPECT_GT(s.edges_injected, 4000u) << ch;
        EXPECT_EQ(s.isr_count, run.isr_entries[ch].size());
        // Every injected edge either started an ISR or was lost; at most one
        // edge can still be pending when the run stops.
        EXPECT_LE(s.isr_count + s.lost_edges, s.edges_injected);
        EXPECT_GE(s.isr_count + s.lost_edges + 1, s.edges_injected);
    }
    // Count1/Count2 are read between the UDR0 write of "END"'s 'E' and that of
    // the count's first digit; the printed value lies between the ISR counts
    // at those two cycles.
    const std::size_t end_pos = run.text.find("END\r\n");
    ASSERT_NE(end_pos, std::string::npos);
    const hil::Cycles read_from = run.bytes[end_pos].cycle;
    const hil::Cycles read_by1 = run.bytes[end_pos + 5].cycle;
    const std::size_t count2_pos = run.text.find("\r\n", end_pos + 5) + 2;
    const hil::Cycles read_by2 = run.bytes[count2_pos].cycle;
    const double c1 = *run.report.count1;
    const double c2 = *run.report.count2;
    EXPECT_GE(c1, static_cast<double>(isr_count_by(run.isr_entries[0], read_from)));
    EXPECT_LE(c1, static_cast<double>(isr_count_by(run.isr_entries[0], read_by1)));
    EXPECT_GE(c2, static_cast<double>(isr_count_by(run.isr_entries[1], read_from)));
    EXPECT_LE(c2, static_cast<double>(isr_count_by(run.isr_entries[1], read_by2)));
}

TEST(PlantCoupler, EepromLogIsContinuousAndEndsAtTheFirmwareEstimate) {
    const auto& run = case1();
    ASSERT_EQ(run.log.size(), 120u);  // 1200 iterations, one sample per 10
    // Samples are 10 iterations (~0.104 s) apart. The robot's top speed is
    // 210 RPM x 2 pi / 60 x 0.0322 m = 0.708 m/s: at most 7.4 cm per sample,
    // plus 2 counts (8 mm) of quantisation: a larger jump is a decoding error.
    // On the circle (after the first second's dash from its centre, at up to
    // full speed) the goal moves 0.6 m x 0.5236 rad/s x 0.104 s = 3.3 cm:
    // there no jump exceeds 5 cm.
    for (std::size_t k = 1; k < run.log.size(); ++k) {
        const double jump = std::hypot(run.log[k].x_m - run.log[k - 1].x_m, run.log[k].y_m - run.log[k - 1].y_m);
        EXPECT_LT(jump, 0.082) << "sample " << k;
        if (k >= 10) {
            EXPECT_LT(jump, 0.05) << "sample " << k;
        }
    }
    // The last sample is int(E * 250) / 250 of the same Ex, Ey the firmware
    // holds at "END" (no iteration in between): within one count, 4 mm.
    EXPECT_NEAR(run.log.back().x_m, run.ex, 0.004);
    EXPECT_NEAR(run.log.back().y_m, run.ey, 0.004);
    // And the firmware's estimate is near the truth (same bound as above).
    EXPECT_LT(std::hypot(run.ex - run.end_truth.x_m, run.ey - run.end_truth.y_m), 0.10);
}

TEST(PlantCoupler, InputLatencyIsBelowOneCouplingStep) {
    const auto& run = case1();
    const hil::CouplerConfig defaults = hil::resolved(hil::CouplerConfig{}, kUnoClockHz);
    EXPECT_GT(run.max_latency, 0u);
    EXPECT_LE(run.max_latency, defaults.step_cycles);
}

TEST(PlantCoupler, DefaultPeriodsAreTimesAtTheBoardsClock) {
    // 62.5 us and 1 ms: 1000 and 16,000 cycles at 16 MHz, 500 and 8,000 at 8 MHz.
    const hil::CouplerConfig uno = hil::resolved(hil::CouplerConfig{}, 16'000'000);
    EXPECT_EQ(uno.step_cycles, 1000u);
    EXPECT_EQ(uno.truth_period_cycles, 16'000u);
    const hil::CouplerConfig pro_mini = hil::resolved(hil::CouplerConfig{}, 8'000'000);
    EXPECT_EQ(pro_mini.step_cycles, 500u);
    EXPECT_EQ(pro_mini.truth_period_cycles, 8'000u);
    hil::CouplerConfig given;
    given.step_cycles = 250;
    EXPECT_EQ(hil::resolved(given, 8'000'000).step_cycles, 250u);  // a given step is kept
}

TEST(PlantCoupler, SwappedEncoderWiringBreaksTracking) {
    hil::RigConfig config;
    config.board.wheel[0].encoder.pin[0] = 3;
    config.board.wheel[1].encoder.pin[0] = 2;
    const auto run = run_rig_case('1', config);
    expect_completed_and_moved(run);
    // Each wheel's count feeds the other wheel's estimate: the controller
    // steers the wrong way and never converges on the circle.
    EXPECT_GT(distance_to_circle(run.end_truth, 0.6), 0.3);
}

TEST(PlantCoupler, SwappedEnableWiringBreaksTracking) {
    hil::RigConfig config;
    config.board.wheel[0].motor[hil::DriverRole::pwm].pin = 11;
    config.board.wheel[1].motor[hil::DriverRole::pwm].pin = 10;
    const auto run = run_rig_case('1', config);
    expect_completed_and_moved(run);
    EXPECT_GT(distance_to_circle(run.end_truth, 0.6), 0.3);
}

TEST(PlantCoupler, AWheelWithoutEncoderTurnsButDrivesNoPin) {
    // The left encoder unwired: the firmware counts nothing on pin 3 (its
    // report's Count2 is 0) while its right wheel keeps counting; the left
    // motor still turns in the plant (the firmware, seeing it stand, drives it).
    hil::RigConfig config;
    config.board.wheel[1].encoder.kind = hil::EncoderKind::none;
    const auto run = run_rig_case('1', config);
    EXPECT_EQ(run.encoder[1].edges_injected, 0u);
    EXPECT_EQ(run.encoder[1].isr_count, 0u);
    EXPECT_GT(run.encoder[0].edges_injected, 1000u);
    ASSERT_TRUE(run.report_complete);
    EXPECT_EQ(run.report.count2.value_or(-1), 0.0);
    EXPECT_GT(run.report.count1.value_or(0), 1000.0);
    EXPECT_GT(std::abs(run.motor_angle_rad[1]), kTurnedRad);
}

TEST(PlantCoupler, AveragedPwmKeepsTheLoopTimingButMovesTheEndPose) {
    hil::RigConfig config;
    config.coupler.mode = plant::DriveMode::averaged;
    const auto avg = run_rig_case('1', config);
    const auto& sw = case1();
    ASSERT_TRUE(avg.report_complete);
    // The firmware's timing does not depend on the bridge model...
    EXPECT_NEAR(avg.mean_period_s, sw.mean_period_s, 0.01 * sw.mean_period_s);
    // ...but the robot does: with switched PWM the bridge is off between
    // pulses and the motors coast (discontinuous current), so the same duty
    // drives them faster than the averaged duty x V. Measured: the end poses
    // differ by about 0.13 m.
    const double moved = std::hypot(avg.end_truth.x_m - sw.end_truth.x_m, avg.end_truth.y_m - sw.end_truth.y_m);
    EXPECT_GT(moved, 0.05);
    EXPECT_LT(moved, 0.3);
}

TEST(PlantCoupler, DatasheetEepromTimingLengthensTheLoggingIterations) {
    hil::RigConfig config;
    config.eeprom_timing = hil::EepromTimingMode::kInstant;
    const auto instant = run_rig_case('1', config);
    const auto& datasheet = case1();
    ASSERT_TRUE(instant.report_complete);
    // eeprom_write_byte waits for the previous write before starting its own:
    // the y byte waits 3.296 ms for the x byte, then programs while the loop
    // goes on. One write time per 10 iterations: +0.33 ms on the mean period.
    const double extra_ms = (datasheet.mean_period_s - instant.mean_period_s) * 1e3;
    EXPECT_NEAR(extra_ms, 3.296 / 10.0, 0.03);
}

TEST(PlantCoupler, RejectsATruthPeriodThatIsNotAMultipleOfTheStep) {
    hil::RigConfig config;
    config.coupler.step_cycles = 1000;
    config.coupler.truth_period_cycles = 1500;
    EXPECT_THROW(hil::RobotRig(hil::ElfImage::read(firmware_elf()), config), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::test
