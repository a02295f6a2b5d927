#include "tools/hostsim/drive_command.hpp"

#include <gtest/gtest.h>

#include "plant/robot_params.hpp"

namespace ddmr::hostsim {
namespace {

// The sketch's first iteration (kanayama_test.cpp): v = 0.5999593, w = 1.8.
//   Vdc1 = int(255 x 48 x 0.0054 x (30.3 v + 1.92 w) x 0.164)
//        = int(66.096 x (18.178766 + 3.456) x 0.164) = int(234.516) = 234
//   Vdc2 = int(66.096 x (18.178766 - 3.456) x 0.164) = int(159.592) = 159
TEST(DriveCommand, FirmwaresFirstIterationGives234And159) {
    const VelocityCommand<float> c{0.6F - 0.2F * 2.0367e-4F, 1.8F};
    const WheelSpeeds<float> phi = firmware_wheel_speeds(c);
    const float gr = 48.0F, ka = 0.0054F, batt = 0.164F;
    const float u1 = drive_value_255(gr, ka, phi.right_rad_s, batt);
    const float u2 = drive_value_255(gr, ka, phi.left_rad_s, batt);
    EXPECT_NEAR(static_cast<double>(u1), 234.516, 2e-3);
    EXPECT_NEAR(static_cast<double>(u2), 159.592, 2e-3);
    EXPECT_EQ(firmware_int(static_cast<double>(u1)), 234);
    EXPECT_EQ(firmware_int(static_cast<double>(u2)), 159);
    const BridgeCommand b1 = quantised_drive(234, pwm_timer_of_motor(0), false);
    EXPECT_TRUE(b1.forward);
    EXPECT_EQ(b1.ocr, 234);
    EXPECT_DOUBLE_EQ(b1.duty, 234.0 / 255.0);
}

// Inverse of eq. (6) and back: v = 0.3 m/s, w = 0.5 rad/s, r = 0.0322 m, L = 0.064 m:
//   phi_1 = (0.3 + 0.032) / 0.0322 = 10.3106 rad/s, phi_2 = (0.3 - 0.032) / 0.0322 = 8.3230 rad/s.
TEST(DriveCommand, InverseKinematicsRoundTrip) {
    const plant::DiffDriveParams p = plant::default_robot_params().kinematics;
    const WheelSpeeds<double> w = inverse_kinematics(p, VelocityCommand<double>{0.3, 0.5});
    EXPECT_NEAR(w.right_rad_s, 0.332 / 0.0322, 1e-12);
    EXPECT_NEAR(w.left_rad_s, 0.268 / 0.0322, 1e-12);
    const plant::BodyVelocity b = plant::body_velocity(p, w.right_rad_s, w.left_rad_s);
    EXPECT_NEAR(b.v_m_s, 0.3, 1e-14);
    EXPECT_NEAR(b.omega_rad_s, 0.5, 1e-14);
}

TEST(DriveCommand, SketchInverseImpliesR33mmAndL63mm) {
    // 30.3 = 1 / 0.033 m, 1.92 = 0.0634 / 0.033: the sketch's feed-forward
    // equals the inverse of eq. (6) for r = 1/30.3 m and L = 1.92 / 30.3 m.
    plant::DiffDriveParams p;
    p.wheel_radius_right_m = p.wheel_radius_left_m = 1.0 / 30.3;
    p.half_axle_m = 1.92 / 30.3;
    const VelocityCommand<double> c{0.25, -0.7};
    const WheelSpeeds<double> a = firmware_wheel_speeds(c);
    const WheelSpeeds<double> b = inverse_kinematics(p, c);
    EXPECT_NEAR(a.right_rad_s, b.right_rad_s, 1e-12);
    EXPECT_NEAR(a.left_rad_s, b.left_rad_s, 1e-12);
}

TEST(DriveCommand, FirmwareIntTruncatesTowardZero) {
    EXPECT_EQ(firmware_int(234.99), 234);
    EXPECT_EQ(firmware_int(-0.7), 0);
    EXPECT_EQ(firmware_int(-30.9), -30);
    EXPECT_EQ(firmware_int(1e9), 32767);
    EXPECT_EQ(firmware_int(-1e9), -32768);
}

TEST(DriveCommand, QuantisedClampAndDirectionAsTheSketch) {
    const BridgeCommand high = quantised_drive(300, PwmTimer::timer1_ocr1b, false);
    EXPECT_EQ(high.value, 255);  // if (Vdc1>255) Vdc1=255
    EXPECT_TRUE(high.forward);
    EXPECT_DOUBLE_EQ(high.duty, 1.0);
    const BridgeCommand zero = quantised_drive(0, PwmTimer::timer2_ocr2a, false);
    EXPECT_FALSE(zero.forward);  // Vdc = 0 leaves the direction pin as it was
    EXPECT_DOUBLE_EQ(zero.duty, 0.0);
    EXPECT_TRUE(quantised_drive(0, PwmTimer::timer2_ocr2a, true).forward);
}

TEST(DriveCommand, NegativeValueOnPin10StaysLowOnPin11Wraps) {
    // analogWrite(10, -30): OCR1B = 65506 > TOP, never matched: low, reverse.
    const BridgeCommand m1 = quantised_drive(-30, PwmTimer::timer1_ocr1b, true);
    EXPECT_FALSE(m1.forward);
    EXPECT_EQ(m1.value, -30);
    EXPECT_DOUBLE_EQ(m1.duty, 0.0);
    // analogWrite(11, -30): OCR2A = 226: 88.6 % in reverse.
    const BridgeCommand m2 = quantised_drive(-30, PwmTimer::timer2_ocr2a, true);
    EXPECT_FALSE(m2.forward);
    EXPECT_EQ(m2.ocr, 226);
    EXPECT_DOUBLE_EQ(m2.duty, 226.0 / 255.0);
    // No lower clamp in the sketch: -300 -> low byte 212; -1 -> 255 (fully on).
    EXPECT_EQ(quantised_drive(-300, PwmTimer::timer2_ocr2a, true).ocr, 212);
    EXPECT_DOUBLE_EQ(quantised_drive(-1, PwmTimer::timer2_ocr2a, true).duty, 1.0);
}

TEST(DriveCommand, ContinuousDriveClampsToTheBattery) {
    const BridgeCommand half = continuous_drive(-127.5, true);
    EXPECT_DOUBLE_EQ(half.duty, 0.5);
    EXPECT_FALSE(half.forward);
    EXPECT_EQ(half.value, 0);
    EXPECT_DOUBLE_EQ(continuous_drive(400.0, false).duty, 1.0);  // |V| > V_batt
    EXPECT_TRUE(continuous_drive(400.0, false).forward);
    EXPECT_FALSE(continuous_drive(0.0, false).forward);  // u = 0: unchanged
    EXPECT_DOUBLE_EQ(continuous_drive(0.5, true).duty, 0.5 / 255.0);  // no quantisation
}

}  // namespace
}  // namespace ddmr::hostsim
