// Identifiability worked out by hand on linear predictions, and on the
// reference robot's log: what the firmware's log cannot see.
#include "calibrate/identifiability.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "calibrate/log_objective.hpp"
#include "plant/param_access.hpp"
#include "support/rig_run.hpp"

namespace ddmr::calibrate {
namespace {

// y = (t1, t2, t1 + t2) at t = (1, 2), sigma = 0.01. With S = dy/dln t =
// [[1, 0], [0, 2], [1, 2]]: F = S^T S / sigma^2 = [[2, 2], [2, 8]] x 1e4,
// C = F^-1 = [[8, -2], [-2, 2]] / 12 x 1e-4: sd(ln t1) = 0.008165,
// sd(ln t2) = 0.004082, correlation -1/6 / sqrt(2/3 x 1/6) = -0.5;
// singular values sqrt(5 +- sqrt(13)) / 0.01 = 293.35, 118.08.
TEST(Identifiability, ALinearPredictionByHand) {
    const auto predict = [](const std::vector<double>& t) { return std::vector<double>{t[0], t[1], t[0] + t[1]}; };
    const Identifiability id = analyse_identifiability(predict, {"a", "b"}, {1.0, 2.0}, 0.01);
    ASSERT_EQ(id.params.size(), 2u);
    // Central differences on ln t of a linear map: exact to (1 + h^2/6).
    EXPECT_NEAR(id.params[0].relative_sd, 0.0081650, 1e-6);
    EXPECT_NEAR(id.params[1].relative_sd, 0.0040825, 1e-6);
    EXPECT_NEAR(id.correlation(0, 1), -0.5, 1e-6);
    EXPECT_NEAR(id.correlation(1, 1), 1.0, 1e-12);
    ASSERT_EQ(id.singular_values.size(), 2u);
    EXPECT_NEAR(id.singular_values[0], 293.35, 0.01);
    EXPECT_NEAR(id.singular_values[1], 118.08, 0.01);
    EXPECT_NEAR(id.params[0].ci_lo, std::exp(-1.959964 * 0.0081650), 1e-5);
    EXPECT_NEAR(id.params[0].ci_hi, std::exp(1.959964 * 0.0081650), 1e-5);
    EXPECT_NEAR(id.params[1].ci_hi, 2.0 * std::exp(1.959964 * 0.0040825), 1e-5);
    EXPECT_TRUE(id.params[0].identifiable);
    EXPECT_TRUE(id.params[1].identifiable);
    // y = (a + b, a + 1.01 b) at (1, 1): S = [[1, 1], [1, 1.01]], S^-1 =
    // [[101, -100], [-100, 100]], C = sigma^2 S^-1 S^-T: var(ln a) = 20201
    // sigma^2, correlation -20100 / sqrt(20201 x 20000) = -1.000. At sigma =
    // 0.001: sd 0.142, a factor exp(1.96 x 0.142) = 1.32: pinned; at 0.005:
    // sd 0.711, a factor 4.0: only a + b is seen.
    const auto nearly = [](const std::vector<double>& t) { return std::vector<double>{t[0] + t[1], t[0] + 1.01 * t[1]}; };
    const Identifiability fine = analyse_identifiability(nearly, {"a", "b"}, {1.0, 1.0}, 0.001);
    EXPECT_NEAR(fine.params[0].relative_sd, 0.001 * std::sqrt(20201.0), 1e-4);
    EXPECT_TRUE(fine.params[0].identifiable);
    const Identifiability traded = analyse_identifiability(nearly, {"a", "b"}, {1.0, 1.0}, 0.005);
    EXPECT_FALSE(traded.params[0].identifiable);
    EXPECT_NE(traded.params[0].reason.find("cannot separate it from b (correlation -1.000)"), std::string::npos)
        << traded.params[0].reason;
    EXPECT_NE(traded.params[1].reason.find("cannot separate it from a"), std::string::npos) << traded.params[1].reason;
}

TEST(Identifiability, AParameterThePredictionIgnoresAndATradeOff) {
    const auto ignores_b = [](const std::vector<double>& t) { return std::vector<double>{t[0], 2.0 * t[0]}; };
    const Identifiability a = analyse_identifiability(ignores_b, {"a", "b"}, {1.0, 1.0}, 0.01);
    EXPECT_TRUE(a.params[0].identifiable);
    EXPECT_FALSE(a.params[1].identifiable);
    EXPECT_NE(a.params[1].reason.find("the log does not depend on it"), std::string::npos) << a.params[1].reason;
    // Only the product is seen: y = (a b, 2 a b).
    const auto product = [](const std::vector<double>& t) { return std::vector<double>{t[0] * t[1], 2.0 * t[0] * t[1]}; };
    const Identifiability p = analyse_identifiability(product, {"R", "K"}, {5.0, 0.004}, 0.0001);
    EXPECT_FALSE(p.params[0].identifiable);
    EXPECT_FALSE(p.params[1].identifiable);
    EXPECT_NE(p.params[0].reason.find("cannot separate it from K"), std::string::npos) << p.params[0].reason;
    EXPECT_LT(p.singular_values[1], 1e-6 * p.singular_values[0]);
}

// The same linear prediction with a model tolerance t = 0.02: over its 3
// values the half-width is max(1.96 sd, t sqrt(3) sd / sigma) = 3.46 sd
// (t sqrt(3) / sigma = 3.464 > 1.96): a model right only to 2 cm cannot tell
// apart values it predicts to within 2 cm, however sharp the noise.
TEST(Identifiability, AModelToleranceWidensTheIntervals) {
    const auto predict = [](const std::vector<double>& t) { return std::vector<double>{t[0], t[1], t[0] + t[1]}; };
    const Identifiability sharp = analyse_identifiability(predict, {"a", "b"}, {1.0, 2.0}, 0.01, 0.01, 0.0);
    const Identifiability wide = analyse_identifiability(predict, {"a", "b"}, {1.0, 2.0}, 0.01, 0.01, 0.02);
    EXPECT_NEAR(sharp.params[0].half_width, 1.959964 * 0.0081650, 1e-6);
    EXPECT_NEAR(wide.params[0].half_width, 0.02 * std::sqrt(3.0) / 0.01 * 0.0081650, 1e-6);
    EXPECT_NEAR(wide.params[1].ci_hi, 2.0 * std::exp(0.02 * std::sqrt(3.0) / 0.01 * 0.0040825), 1e-5);
    EXPECT_DOUBLE_EQ(wide.params[0].relative_sd, sharp.params[0].relative_sd);  // the statistics do not change
}

// Candidates a, b = 2 a (the same column twice over: only their combination
// shows) and c on its own axis. The most visible, b, is kept; a is refused
// as inseparable from it; c is kept. With a half-width limit below c's, c is
// refused too, with the width it gets.
TEST(Identifiability, SelectionKeepsWhatTheLogPinsDownTogether) {
    Eigen::MatrixXd s(4, 3);
    s << 1, 2, 0,  //
        1, 2, 0,   //
        0, 0, 1,   //
        0, 0, 1;
    const std::vector<std::string> keys = {"a", "b", "c"};
    const std::vector<double> at = {1.0, 1.0, 1.0};
    const Selection sel = select_identifiable(s, keys, at, 0.5, 0.01);
    ASSERT_EQ(sel.chosen, (std::vector<std::size_t>{1, 2}));
    ASSERT_EQ(sel.left_out.size(), 1u);
    EXPECT_EQ(sel.left_out[0].index, 0u);
    EXPECT_NE(sel.left_out[0].reason.find("cannot separate it from b"), std::string::npos) << sel.left_out[0].reason;
    // c alone: sd = sigma / |column| = 0.01 / sqrt(2); half-width 1.96 x that = 0.01386.
    const Selection strict = select_identifiable(s, keys, at, 0.01, 0.01);
    ASSERT_EQ(strict.chosen, (std::vector<std::size_t>{1}));
    EXPECT_EQ(strict.left_out.back().index, 2u);
    EXPECT_NE(strict.left_out.back().reason.find("within x1.01"), std::string::npos) << strict.left_out.back().reason;
}

TEST(Identifiability, BadInputIsRefused) {
    const auto f = [](const std::vector<double>& t) { return t; };
    EXPECT_THROW(analyse_identifiability(f, {"a"}, {-1.0}), std::invalid_argument);
    EXPECT_THROW(analyse_identifiability(f, {"a", "b"}, {1.0}), std::invalid_argument);
    EXPECT_THROW(analyse_identifiability(f, {"a"}, {1.0}, 0.0), std::invalid_argument);
}

// The reference robot's case-1 log (the HIL, default plant): the right
// motor's resistance moves the logged track; the right wheel's radius does
// not, since the log holds the firmware's belief (its odometry, with its own
// constants, on the encoder counts), which the true radius leaves alone.
TEST(Identifiability, TheFirmwaresLogCannotSeeTheWheelRadius) {
    const test::RigRun robot = test::run_rig_case('1');
    ASSERT_TRUE(robot.report_complete);
    const LogRun run{parse_robot_log(robot.text, "robot.txt"), 0, 0};
    ObjectiveConfig objective;
    objective.base.pwm = hostsim::PwmModel::switched;
    objective.base.period_s = 0.01044;
    const std::vector<std::string> keys = {"motor1.resistance_ohm", "kinematics.wheel_radius_right_m"};
    const plant::RobotParams start = plant::default_robot_params();
    const auto predict = [&](const std::vector<double>& v) {
        plant::RobotParams p = start;
        for (std::size_t i = 0; i < v.size(); ++i) *plant::find_param(p, keys[i])->value = v[i];
        return predicted_log(p, run, objective);
    };
    const Identifiability id = analyse_identifiability(predict, keys, {5.32, start.kinematics.wheel_radius_right_m});
    EXPECT_TRUE(id.params[0].identifiable) << id.params[0].reason;
    EXPECT_LT(id.params[0].ci_hi / id.params[0].ci_lo, 1.05);  // R pinned to a few percent
    EXPECT_FALSE(id.params[1].identifiable);
    EXPECT_NE(id.params[1].reason.find("the log does not depend on it"), std::string::npos) << id.params[1].reason;
}

}  // namespace
}  // namespace ddmr::calibrate
