// The objective on the reference firmware's own case-1 log from the HIL
// (the robot's closed loop on the default plant):
// the host simulation's firmware model of the same (default) plant
// reproduces it to a few millimetres, a plant 30 % off does not, and the
// encoder phases and the sample range behave as documented.
#include "calibrate/log_objective.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/param_access.hpp"
#include "support/rig_run.hpp"

namespace ddmr::calibrate {
namespace {

const RobotLog& case1_log() {
    static const RobotLog log = [] {
        const test::RigRun run = test::run_rig_case('1');  // the default plant, closed loop
        if (!run.report_complete) throw std::runtime_error("case 1 did not complete");
        return parse_robot_log(run.text, "uart.txt");
    }();
    return log;
}

/// The HIL's plant: switched PWM, its measured loop period.
ObjectiveConfig hil_like() {
    ObjectiveConfig c;
    c.base.pwm = hostsim::PwmModel::switched;
    c.base.period_s = 0.01044;
    return c;
}

TEST(LogObjective, TheLoggedPositionsUnwrapFromTheOrigin) {
    RobotLog log;
    log.samples = {{0, 255, 1}, {10, 250, 2}, {200, 100, 3}};
    const auto p = logged_positions(log);
    ASSERT_EQ(p.size(), 3u);
    EXPECT_DOUBLE_EQ(p[0].second, -1.0 / 250.0);  // sample 0 signed: 255 = -1
    EXPECT_DOUBLE_EQ(p[1].first, 10.0 / 250.0);
    EXPECT_DOUBLE_EQ(p[1].second, -6.0 / 250.0);
    EXPECT_DOUBLE_EQ(p[2].first, -56.0 / 250.0);  // 10 -> 200: -66 is nearer than +190
    EXPECT_DOUBLE_EQ(p[2].second, 100.0 / 250.0);
}

TEST(LogObjective, TheSamePlantReproducesTheLogAPlantOffDoesNot) {
    const LogRun run{case1_log(), 0, 0};
    ASSERT_EQ(run.log.samples.size(), 120u);
    const Evaluation same = evaluate(plant::default_robot_params(), run, hil_like());
    EXPECT_FALSE(same.plant_failed);
    EXPECT_EQ(same.metrics.samples, 120u);
    // The host model against the HIL with the real firmware: inside the
    // log's 4 mm cells but for a fraction of a millimetre (measured 0.5 mm).
    EXPECT_LT(same.metrics.rms_m, 0.002) << same.metrics.rms_m;
    EXPECT_NEAR(same.metrics.count1, static_cast<double>(run.log.count1), 0.01 * static_cast<double>(run.log.count1));
    EXPECT_NEAR(same.metrics.count2, static_cast<double>(run.log.count2), 0.01 * static_cast<double>(run.log.count2));
    plant::RobotParams off = plant::default_robot_params();
    *plant::find_param(off, "motor1.resistance_ohm")->value *= 1.3;
    const Evaluation worse = evaluate(off, run, hil_like());
    EXPECT_GT(worse.loss, 2.0 * same.loss) << worse.loss << " vs " << same.loss;
    EXPECT_GT(worse.metrics.rms_m, 0.03);  // measured 74 mm
    // Deterministic.
    EXPECT_EQ(evaluate(off, run, hil_like()).loss, worse.loss);
}

TEST(LogObjective, ThePartOfTheLogThatCounts) {
    const LogRun first_half{case1_log(), 0, 60};
    const LogRun second_half{case1_log(), 60, 0};
    const Evaluation a = evaluate(plant::default_robot_params(), first_half, hil_like());
    const Evaluation b = evaluate(plant::default_robot_params(), second_half, hil_like());
    EXPECT_EQ(a.metrics.samples, 60u);
    EXPECT_EQ(b.metrics.samples, 60u);
    EXPECT_NE(a.loss, b.loss);  // each half scores its own samples
    // The totals count only with the run's end: x, y of 60 samples, then the two totals.
    EXPECT_EQ(predicted_log(plant::default_robot_params(), first_half, hil_like()).size(), 120u);
    EXPECT_EQ(predicted_log(plant::default_robot_params(), second_half, hil_like()).size(), 122u);
    const LogRun empty{case1_log(), 60, 60};
    EXPECT_THROW(evaluate(plant::default_robot_params(), empty, hil_like()), std::invalid_argument);
    ObjectiveConfig bad = hil_like();
    bad.encoder_phases = {1.0};
    EXPECT_THROW(evaluate(plant::default_robot_params(), first_half, bad), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::calibrate
