// Tests for plant/robot_faults and the fault entry points of plant::Robot.
// Numbers worked out by hand from the defaults (plant/params/default.yaml):
// L298 drop 1.4 V, R_a1 = 5.32 ohm, R_b = 0.037 ohm.
#include "plant/robot_faults.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>

#include "plant/robot.hpp"

namespace ddmr::plant {
namespace {

RobotInput full_averaged(double d1, double d2) {
    RobotInput in;
    in.mode = DriveMode::averaged;
    in.bridge[0].duty = d1;
    in.bridge[1].duty = d2;
    return in;
}

/// Runs `seconds` in 1 ms steps; returns the edges reported per encoder.
std::array<std::size_t, 2> run(Robot& r, double seconds) {
    EdgeBuffer e;
    std::array<std::size_t, 2> edges{};
    const auto n = static_cast<long>(std::lround(seconds / 1e-3));
    for (long k = 0; k < n; ++k) {
        e.clear();
        EXPECT_EQ(r.step(1e-3, e).status, StepStatus::ok);
        for (std::size_t i = 0; i < e.size(); ++i) ++edges[e.data()[i].channel];
    }
    return edges;
}

TEST(RobotFaults, LockedShaftDrawsTheStallCurrentAndReportsNoEdges) {
    Robot r;
    RobotFaults f;
    f.shaft_locked[0] = true;
    f.source_V = 6.1;  // no sag: the stall current is exact
    r.set_faults(f);
    r.set_input(full_averaged(1.0, 0.0));
    const auto edges = run(r, 0.05);  // >> L/R = 2.3 mH / 5.32 ohm = 0.43 ms
    // I = (6.1 - 1.4) / (5.32 + 0.037) = 0.877357 A; only motor 1 draws.
    // The held shaft never turns, so there is no back-EMF at all; after
    // 0.05 s = 116 L/R the transient is below e^-116.
    EXPECT_NEAR(r.motor_current_A(0), 4.7 / 5.357, 1e-12);
    EXPECT_EQ(r.motor_speed_rad_s(0), 0.0);
    EXPECT_EQ(r.motor_angle_rad(0), 0.0);
    EXPECT_EQ(edges[0], 0U);
    EXPECT_EQ(r.pose().x_m, 0.0);
}

TEST(RobotFaults, ReleasedShaftTurnsAgain) {
    Robot r;
    RobotFaults f;
    f.shaft_locked[0] = true;
    r.set_faults(f);
    r.set_input(full_averaged(1.0, 1.0));
    const auto locked = run(r, 0.2);
    EXPECT_EQ(locked[0], 0U);
    EXPECT_GT(locked[1], 0U);
    r.set_faults(RobotFaults{});
    const auto free = run(r, 0.2);
    EXPECT_GT(free[0], 0U);
    EXPECT_GT(r.motor_speed_rad_s(0), 0.0);
}

TEST(RobotFaults, BenchSupplySetsTheBatteryVoltage) {
    Robot r;
    RobotFaults f;
    f.source_V = 5.2;
    r.set_faults(f);
    EXPECT_DOUBLE_EQ(r.battery_voltage_V(), 5.2);  // no current yet
    f.shaft_locked = {true, true};
    r.set_faults(f);
    r.set_input(full_averaged(1.0, 0.0));
    run(r, 0.05);
    // (5.2 - 1.4) / (5.32 + 0.037) = 0.709352 A; terminal = 5.2 - 0.037 I.
    EXPECT_NEAR(r.motor_current_A(0), 3.8 / 5.357, 1e-12);
    EXPECT_NEAR(r.battery_voltage_V(), 5.2 - 0.037 * 3.8 / 5.357, 1e-4);
}

TEST(RobotFaults, SlipScalesThePoseButNotTheEncoders) {
    Robot grip, slip;
    RobotFaults f;
    f.traction = {0.5, 0.5};
    slip.set_faults(f);
    grip.set_input(full_averaged(0.6, 0.6));
    slip.set_input(full_averaged(0.6, 0.6));
    const auto e_grip = run(grip, 1.0);
    const auto e_slip = run(slip, 1.0);
    EXPECT_EQ(e_grip, e_slip);
    // Equal traction on both wheels halves every wheel turn: the arc is
    // exactly half as long, with half the heading change.
    const double d_grip = std::hypot(grip.pose().x_m, grip.pose().y_m);
    const double d_slip = std::hypot(slip.pose().x_m, slip.pose().y_m);
    ASSERT_GT(d_grip, 0.05);
    EXPECT_NEAR(d_slip / d_grip, 0.5, 0.01);
    EXPECT_NEAR(slip.pose().theta_rad, 0.5 * grip.pose().theta_rad, 1e-9);
}

TEST(RobotFaults, DisplaceMovesOnlyThePose) {
    Robot r;
    r.displace(Pose{0.05, -0.02, 0.3});
    EXPECT_DOUBLE_EQ(r.pose().x_m, 0.05);
    EXPECT_DOUBLE_EQ(r.pose().y_m, -0.02);
    EXPECT_DOUBLE_EQ(r.pose().theta_rad, 0.3);
    EXPECT_EQ(r.motor_angle_rad(0), 0.0);
}

TEST(RobotFaults, MissedEdgesDropAboutTheirShare) {
    Robot clean, lossy;
    lossy.set_missed_edge_probability(0, 0.25);
    clean.set_input(full_averaged(0.8, 0.8));
    lossy.set_input(full_averaged(0.8, 0.8));
    const auto a = run(clean, 1.0);
    const auto b = run(lossy, 1.0);
    ASSERT_GT(a[0], 800U);
    EXPECT_EQ(a[1], b[1]);
    const double kept = static_cast<double>(b[0]) / static_cast<double>(a[0]);
    EXPECT_NEAR(kept, 0.75, 0.05);  // binomial, n > 800: sd < 0.016
}

TEST(RobotFaults, OutOfRangeValuesAreRefused) {
    Robot r;
    RobotFaults f;
    f.traction[1] = 1.5;
    EXPECT_THROW(r.set_faults(f), std::invalid_argument);
    f = RobotFaults{};
    f.source_V = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(r.set_faults(f), std::invalid_argument);
    f.source_V = 0.0;
    EXPECT_THROW(r.set_faults(f), std::invalid_argument);
    EXPECT_THROW(r.set_missed_edge_probability(0, 0.6), std::invalid_argument);
    EXPECT_THROW(r.set_missed_edge_probability(2, 0.1), std::invalid_argument);
    EXPECT_TRUE(r.faults().traction[1] == 1.0);  // a refused set leaves the faults as they were
}

}  // namespace
}  // namespace ddmr::plant
