#include "tools/hostsim/firmware_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::hostsim {
namespace {

// 100 edges on each wheel in one 10 ms pass:
//   phi1dot = phi2dot = 100 x 0.016362 x 100 = 163.62 rad/s
//   Vel = 0.5 x 0.03215 x 327.24 = 5.2603830 m/s, Omega = 0
//   Ex = 0.01 x cos(0) x 5.260383 = 0.05260383 m
TEST(FirmwareOdometry, StraightByHand) {
    FirmwareOdometry<double> o;
    const PoseEstimate<double> p = o.update(100, 100);
    EXPECT_NEAR(o.wheel1_rad_s(), 163.62, 1e-12);
    EXPECT_NEAR(o.velocity_m_s(), 5.260383, 1e-9);
    EXPECT_DOUBLE_EQ(o.omega_rad_s(), 0.0);
    EXPECT_NEAR(p.x_m, 0.05260383, 1e-11);
    EXPECT_DOUBLE_EQ(p.y_m, 0.0);
    EXPECT_DOUBLE_EQ(p.theta_rad, 0.0);
}

// 10 edges on the right wheel only:
//   phi1dot = 16.362, Vel = 0.5 x 0.03215 x 16.362 = 0.26301915
//   Omega = 7.874 x 0.03215 x 16.362 = 4.14202... ; Theta = 0.0414202 (heading first)
//   Ex = 0.01 cos(0.0414202) 0.26301915 = 0.00262793, Ey = 0.01 sin(0.0414202) 0.26301915 = 1.08912e-4
TEST(FirmwareOdometry, TurnByHandHeadingFirst) {
    FirmwareOdometry<double> o;
    const PoseEstimate<double> p = o.update(10, 0);
    const double omega = 7.874 * 0.03215 * 16.362;
    EXPECT_NEAR(p.theta_rad, 0.01 * omega, 1e-15);
    EXPECT_NEAR(p.theta_rad, 0.0414202, 1e-7);
    EXPECT_NEAR(p.x_m, 0.01 * std::cos(0.01 * omega) * 0.26301915, 1e-12);
    EXPECT_NEAR(p.y_m, 0.01 * std::sin(0.01 * omega) * 0.26301915, 1e-12);
    EXPECT_NEAR(p.y_m, 1.08912e-4, 1e-9);
}

TEST(FirmwareOdometry, DifferencesOnlyAndNoDirection) {
    // Counts only grow: a second pass with the same counts moves nothing,
    // and the pose is the sum of the passes.
    FirmwareOdometry<double> o;
    o.update(50, 50);
    const PoseEstimate<double> a = o.pose();
    o.update(50, 50);
    EXPECT_EQ(o.pose().x_m, a.x_m);
    EXPECT_DOUBLE_EQ(o.velocity_m_s(), 0.0);
    o.update(100, 100);
    EXPECT_NEAR(o.pose().x_m, 2.0 * a.x_m, 1e-15);
}

TEST(FirmwareOdometry, FloatFollowsDoubleToFloatPrecision) {
    FirmwareOdometry<double> d;
    FirmwareOdometry<float> f;
    std::uint64_t c1 = 0, c2 = 0;
    for (int k = 0; k < 1200; ++k) {  // 12 s of a 0.6 m circle's worth of edges
        c1 += 6;
        c2 += 4;
        d.update(c1, c2);
        f.update(c1, c2);
    }
    EXPECT_NEAR(static_cast<double>(f.pose().x_m), d.pose().x_m, 1e-4);
    EXPECT_NEAR(static_cast<double>(f.pose().theta_rad), d.pose().theta_rad, 1e-4);
    EXPECT_NE(static_cast<double>(f.pose().x_m), d.pose().x_m);  // but not equal: float rounds
}

}  // namespace
}  // namespace ddmr::hostsim
