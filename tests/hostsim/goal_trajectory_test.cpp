#include "tools/hostsim/goal_trajectory.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "plant/units.hpp"

namespace ddmr::hostsim {
namespace {

TEST(GoalTrajectory, FirmwareCasesAreTheSketchsCircles) {
    const CaseSpec c1 = firmware_case(1);
    EXPECT_EQ(c1.radius_m, 0.6);
    EXPECT_EQ(c1.rate_rad_s, 0.5236);
    EXPECT_EQ(c1.heading0_rad, 1.571);
    EXPECT_EQ(c1.duration_s, 12.0);
    EXPECT_TRUE(c1.logs_eeprom);
    const CaseSpec c2 = firmware_case(2);
    EXPECT_EQ(c2.radius_m, 0.4);
    EXPECT_EQ(c2.rate_rad_s, 0.7854);
    EXPECT_EQ(c2.duration_s, 8.0);
    EXPECT_FALSE(c2.logs_eeprom);  // case 2's loop has no EEPROM.write
    EXPECT_THROW(firmware_case(3), std::invalid_argument);
}

TEST(GoalTrajectory, CircleStartsAheadOfTheRobotAndTurnsCounterClockwise) {
    const CaseSpec c = firmware_case(1);
    const GoalPoint<double> g0 = goal_position(c, 0.0);
    EXPECT_DOUBLE_EQ(g0.x_m, 0.6);
    EXPECT_DOUBLE_EQ(g0.y_m, 0.0);
    // A quarter lap: 0.5236 x 3 = 1.5708 rad -> (0.6 cos 1.5708, 0.6 sin 1.5708) = (-2.4e-6, 0.6).
    const GoalPoint<double> g3 = goal_position(c, 3.0);
    EXPECT_NEAR(g3.x_m, 0.6 * std::cos(1.5708), 1e-15);
    EXPECT_NEAR(g3.y_m, 0.6, 1e-9);
    EXPECT_NEAR(goal_heading_rad(c, 3.0), 1.571 + 1.5708, 1e-15);
    // float evaluates the same lines to float precision
    const GoalPoint<float> f3 = goal_position(c, 3.0F);
    EXPECT_NEAR(static_cast<double>(f3.y_m), g3.y_m, 1e-6);
}

TEST(GoalTrajectory, CustomCircleUsesExactRates) {
    const CaseSpec c = circle_case(1.0, 20.0);
    EXPECT_DOUBLE_EQ(c.rate_rad_s, 2.0 * plant::kPi / 20.0);
    EXPECT_DOUBLE_EQ(c.heading0_rad, plant::kPi / 2.0);
    const GoalVelocity v = goal_velocity(c);
    EXPECT_DOUBLE_EQ(v.v_m_s, 2.0 * plant::kPi / 20.0);  // R w = 0.314 m/s (appendix A2's 0.3)
    EXPECT_THROW(circle_case(0.0, 12.0), std::invalid_argument);
    EXPECT_THROW(circle_case(0.6, -1.0), std::invalid_argument);
}

TEST(GoalTrajectory, LineStepJumpsTwentyCentimetresAtTenSeconds) {
    const CaseSpec x = line_step_case(StepAxis::x);
    const CaseSpec y = line_step_case(StepAxis::y);
    // Before the step the goal is 0.5 t along x; at and after it, 0.2 m further along x (or to the left).
    EXPECT_DOUBLE_EQ(goal_position(x, 9.99).x_m, 0.5 * 9.99);
    EXPECT_DOUBLE_EQ(goal_position(x, 10.0).x_m, 5.0 + 0.2);
    EXPECT_DOUBLE_EQ(goal_position(x, 10.0).y_m, 0.0);
    EXPECT_DOUBLE_EQ(goal_position(y, 9.99).y_m, 0.0);
    EXPECT_DOUBLE_EQ(goal_position(y, 12.0).x_m, 6.0);
    EXPECT_DOUBLE_EQ(goal_position(y, 12.0).y_m, 0.2);
    EXPECT_DOUBLE_EQ(goal_heading_rad(y, 12.0), 0.0);
    EXPECT_EQ(goal_velocity(x).v_m_s, 0.5);
    EXPECT_EQ(goal_velocity(x).omega_rad_s, 0.0);
}

}  // namespace
}  // namespace ddmr::hostsim
