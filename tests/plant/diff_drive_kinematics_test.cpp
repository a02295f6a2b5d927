// Tests for plant/diff_drive_kinematics: eqs. (5a), (5b), (10) and the exact
// arc. r = 0.0322 m, L = 0.064 m (Table 2) unless stated.
#include "plant/diff_drive_kinematics.hpp"

#include "plant/units.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::plant {
namespace {

constexpr double kR = 0.0322;
constexpr double kL = 0.064;

TEST(DiffDriveKinematics, BodyVelocityEq5) {
    const DiffDriveParams p;
    // Right 12 rad/s, left 8 rad/s: v = 0.0322*(12+8)/2 = 0.322 m/s,
    // omega = 0.0322*(12-8)/(2*0.064) = 1.00625 rad/s, counter-clockwise (> 0).
    const BodyVelocity b = body_velocity(p, 12.0, 8.0);
    EXPECT_NEAR(b.v_m_s, 0.322, 1e-12);
    EXPECT_NEAR(b.omega_rad_s, 1.00625, 1e-12);
}

TEST(DiffDriveKinematics, EqualWheelSpeedsDriveAStraightLine) {
    const DiffDriveParams p;
    Pose pose{0.0, 0.0, 0.3};
    // 10 rad/s for 1 s in 1000 steps: 0.322 m along heading 0.3 rad.
    for (int k = 0; k < 1000; ++k) advance_exact_arc(p, pose, 10.0 * 1e-3, 10.0 * 1e-3);
    EXPECT_NEAR(pose.x_m, 0.322 * std::cos(0.3), 1e-12);
    EXPECT_NEAR(pose.y_m, 0.322 * std::sin(0.3), 1e-12);
    EXPECT_EQ(pose.theta_rad, 0.3);
}

TEST(DiffDriveKinematics, UnequalSpeedsDriveACircleOfRadiusLSumOverDifference) {
    const DiffDriveParams p;
    // Radius L (w1 + w2) / (w1 - w2) = 0.064 * 20 / 4 = 0.32 m, centre (0, 0.32)
    // (right wheel faster: turns left). A quarter turn takes
    // (pi/2) / 1.00625 = 1.56103 s and ends at (0.32, 0.32), heading pi/2.
    const double t = (kPi / 2) / 1.00625;
    for (int steps : {1, 7, 1000}) {  // exact arc: any step count gives the same point
        Pose pose;
        for (int k = 0; k < steps; ++k) advance_exact_arc(p, pose, 12.0 * t / steps, 8.0 * t / steps);
        EXPECT_NEAR(pose.x_m, 0.32, 1e-12) << steps;
        EXPECT_NEAR(pose.y_m, 0.32, 1e-12) << steps;
        EXPECT_NEAR(pose.theta_rad, kPi / 2, 1e-12) << steps;
    }
}

TEST(DiffDriveKinematics, OppositeSpeedsRotateInPlace) {
    const DiffDriveParams p;
    // omega = 0.0322*(5+5)/(2*0.064) = 2.515625 rad/s, v = 0.
    Pose pose{0.1, -0.2, 0.0};
    for (int k = 0; k < 100; ++k) advance_exact_arc(p, pose, 5.0 * 1e-2, -5.0 * 1e-2);
    EXPECT_NEAR(pose.x_m, 0.1, 1e-15);
    EXPECT_NEAR(pose.y_m, -0.2, 1e-15);
    EXPECT_NEAR(pose.theta_rad, 2.515625, 1e-12);
}

TEST(DiffDriveKinematics, TinyTurnsUseTheStraightLineLimit) {
    const DiffDriveParams p;
    Pose pose;
    // dtheta = 0.0322*2e-9/0.128 ~ 5e-10 rad: the chord factor is 1 to 1e-19.
    advance_exact_arc(p, pose, 1.0 + 1e-9, 1.0 - 1e-9);
    EXPECT_NEAR(pose.x_m, kR, 1e-15);
    EXPECT_TRUE(std::isfinite(pose.y_m));
    // y = ds sin(dtheta/2) = 0.0322 * 2.515625e-10 = 8.1003e-12 m (1e-7 relative:
    // 1 +- 1e-9 carries ~1e-16 of rounding in a 2e-9 difference).
    EXPECT_NEAR(pose.y_m, kR * 0.5 * (kR * 2e-9 / (2 * kL)), 1e-18);
}

TEST(DiffDriveKinematics, ArcAgreesWithEq10Derivative) {
    const DiffDriveParams p;
    const Pose pose{0.0, 0.0, 1.0};
    const Pose d = pose_derivative(p, pose, 12.0, 8.0);
    // x' = 0.322 cos(1), y' = 0.322 sin(1), theta' = 1.00625
    EXPECT_NEAR(d.x_m, 0.322 * std::cos(1.0), 1e-12);
    EXPECT_NEAR(d.y_m, 0.322 * std::sin(1.0), 1e-12);
    EXPECT_NEAR(d.theta_rad, 1.00625, 1e-12);
    Pose q = pose;
    advance_exact_arc(p, q, 12.0 * 1e-6, 8.0 * 1e-6);
    EXPECT_NEAR((q.x_m - pose.x_m) / 1e-6, d.x_m, 1e-6);
    EXPECT_NEAR((q.y_m - pose.y_m) / 1e-6, d.y_m, 1e-6);
}

TEST(DiffDriveKinematics, CarriedHeadingTrigFollowsTheExactArc) {
    // 10 s of a 0.2 m-radius turn at 62.5 us steps (160000 steps, the HIL's
    // step), wheel rotations 0.0125 and 0.0075 rad per step: the carried cos
    // and sin (rotated by each step's turn, recomputed every 1024 steps) give
    // the pose that sin and cos of the full heading give, to rounding.
    const DiffDriveParams p;
    Pose exact;
    Pose carried;
    HeadingTrig trig;
    for (int k = 0; k < 160000; ++k) {
        advance_exact_arc(p, exact, 0.0125, 0.0075);
        advance_exact_arc(p, carried, 0.0125, 0.0075, trig);
    }
    EXPECT_GT(std::abs(exact.theta_rad), 10.0);  // it went round more than once
    EXPECT_NEAR(carried.theta_rad, exact.theta_rad, 1e-12);
    EXPECT_NEAR(carried.x_m, exact.x_m, 1e-12);
    EXPECT_NEAR(carried.y_m, exact.y_m, 1e-12);
}

TEST(DiffDriveKinematics, CarriedHeadingTrigPicksUpAChangedHeading) {
    const DiffDriveParams p;
    Pose pose;
    HeadingTrig trig;
    for (int k = 0; k < 10; ++k) advance_exact_arc(p, pose, 0.01, 0.009, trig);
    // Someone turns the robot (a push, a restored snapshot): the next step
    // must use the new heading, not the carried cos and sin.
    pose.theta_rad = 2.0;
    const Pose before = pose;
    advance_exact_arc(p, pose, 0.01, 0.009, trig);
    // Chord 0.0322 x 0.0095 m x sin(a)/a, a = 0.0322 x 0.001 / 0.256 rad (half
    // the turn), along the mean heading 2 + a.
    const double a = kR * 0.001 / (4 * kL);
    const double chord = kR * 0.0095 * (1.0 - a * a / 6.0);
    EXPECT_NEAR(pose.x_m - before.x_m, chord * std::cos(2.0 + a), 1e-15);
    EXPECT_NEAR(pose.y_m - before.y_m, chord * std::sin(2.0 + a), 1e-15);
}

TEST(DiffDriveKinematics, CarriedHeadingTrigHandsLargeTurnsToTheFullArc) {
    // Opposite wheels, 0.5 rad each: the robot turns 2 x 0.0322 x 0.5 / 0.128
    // = 0.2516 rad in one step, beyond the small-angle series (|turn/2| <= 0.01).
    const DiffDriveParams p;
    Pose a{0.1, 0.2, 0.3};
    Pose b = a;
    HeadingTrig trig;
    advance_exact_arc(p, a, 0.5, -0.5);
    advance_exact_arc(p, b, 0.5, -0.5, trig);
    EXPECT_NEAR(a.x_m, b.x_m, 1e-15);
    EXPECT_NEAR(a.y_m, b.y_m, 1e-15);
    EXPECT_NEAR(a.theta_rad, b.theta_rad, 1e-15);
    EXPECT_NEAR(b.theta_rad, 0.3 + 2 * kR * 0.5 / (2 * kL), 1e-15);
}

}  // namespace
}  // namespace ddmr::plant
