// What an IMU on the chassis senses, worked out by hand for planar motions
// (plant/imu_kinematics.hpp).
#include "plant/imu_kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

constexpr double kDt = 62.5e-6;

/// The pose at time t on a counter-clockwise circle of radius r about the
/// origin at speed v, starting at (r, 0) heading +y.
Pose on_circle(double r, double v, double t) {
    const double phi = v / r * t;
    return {r * std::cos(phi), r * std::sin(phi), phi + kPi / 2};
}

ImuReading circle_reading(double r, double v, const ImuMount& m) {
    return imu_reading(on_circle(r, v, 0), on_circle(r, v, kDt), on_circle(r, v, 2 * kDt), kDt, m);
}

TEST(ImuKinematics, AtRestItReadsOneGUpAndNoRate) {
    const Pose p{0.3, -0.2, 1.0};
    const ImuReading r = imu_reading(p, p, p, kDt, ImuMount{});
    EXPECT_NEAR(r.accel_m_s2.x(), 0.0, 1e-9);
    EXPECT_NEAR(r.accel_m_s2.y(), 0.0, 1e-9);
    EXPECT_DOUBLE_EQ(r.accel_m_s2.z(), kStandardGravity_m_s2);
    EXPECT_DOUBLE_EQ(r.gyro_rad_s.norm(), 0.0);
}

TEST(ImuKinematics, OnACircleTheRateIsVOverRAndTheForcePointsAtTheCentre) {
    // r = 0.5 m at 0.4 m/s: omega = 0.8 rad/s; centripetal v^2 / r = 0.32
    // m/s^2 toward the centre, which is to the robot's left (+y).
    const ImuReading r = circle_reading(0.5, 0.4, ImuMount{});
    EXPECT_NEAR(r.gyro_rad_s.z(), 0.8, 1e-9);
    EXPECT_NEAR(r.accel_m_s2.y(), 0.32, 1e-6);
    EXPECT_NEAR(r.accel_m_s2.x(), 0.0, 1e-6);
}

TEST(ImuKinematics, ASensorAheadOfTheAxleFeelsTheTurnsCentripetalPull) {
    // Turning on the spot at 2 rad/s, a chip 0.05 m ahead of the axle is
    // pulled toward it: -omega^2 x = -0.2 m/s^2 on x.
    const auto spin = [](double t) { return Pose{0.0, 0.0, 2.0 * t}; };
    ImuMount m;
    m.x_m = 0.05;
    const ImuReading r = imu_reading(spin(0), spin(kDt), spin(2 * kDt), kDt, m);
    EXPECT_NEAR(r.accel_m_s2.x(), -0.2, 1e-6);
    EXPECT_NEAR(r.accel_m_s2.y(), 0.0, 1e-6);
    EXPECT_NEAR(r.gyro_rad_s.z(), 2.0, 1e-9);
}

TEST(ImuKinematics, TheChipsOwnAxesTurnAndFlip) {
    // Chip X at 90 degrees (pointing left): the centre, to the left, is its +x.
    ImuMount left;
    left.yaw_rad = kPi / 2;
    const ImuReading a = circle_reading(0.5, 0.4, left);
    EXPECT_NEAR(a.accel_m_s2.x(), 0.32, 1e-6);
    EXPECT_NEAR(a.accel_m_s2.y(), 0.0, 1e-6);
    // Upside down: Y and Z flip: -1 g on z, the yaw rate negative.
    ImuMount down;
    down.z_down = true;
    const ImuReading b = circle_reading(0.5, 0.4, down);
    EXPECT_NEAR(b.gyro_rad_s.z(), -0.8, 1e-9);
    EXPECT_NEAR(b.accel_m_s2.y(), -0.32, 1e-6);
    EXPECT_DOUBLE_EQ(b.accel_m_s2.z(), -kStandardGravity_m_s2);
}

}  // namespace
}  // namespace ddmr::plant
