#include "tools/hostsim/kinematic_plant.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/robot_params.hpp"
#include "plant/units.hpp"

namespace ddmr::hostsim {
namespace {

TEST(KinematicPlant, StraightAtREqualsPhiR) {
    // Both wheels at 10 rad/s, r = 0.0322 m: v = 0.322 m/s; 2 s -> 0.644 m along x.
    KinematicPlant k(plant::default_robot_params().kinematics);
    k.set_wheel_speeds(10.0, 10.0);
    for (int i = 0; i < 100; ++i) k.step(0.02);
    EXPECT_NEAR(k.pose().x_m, 0.644, 1e-12);
    EXPECT_NEAR(k.pose().y_m, 0.0, 1e-15);
    EXPECT_NEAR(k.body_velocity().v_m_s, 0.322, 1e-15);
    EXPECT_NEAR(k.time_s(), 2.0, 1e-12);
}

TEST(KinematicPlant, FullCircleReturnsToStart) {
    // Right wheel 12, left 8 rad/s: v = 0.322 m/s, w = 0.0644 / 0.128 = 0.503125 rad/s;
    // after 2 pi / w the robot is back at the origin (exact arcs: no drift).
    KinematicPlant k(plant::default_robot_params().kinematics);
    k.set_wheel_speeds(12.0, 8.0);
    const double w = 0.0322 * 4.0 / (2.0 * 0.064);
    EXPECT_NEAR(k.body_velocity().omega_rad_s, w, 1e-15);
    const double lap = 2.0 * plant::kPi / w;
    for (int i = 0; i < 1000; ++i) k.step(lap / 1000.0);
    EXPECT_NEAR(k.pose().x_m, 0.0, 1e-12);
    EXPECT_NEAR(k.pose().y_m, 0.0, 1e-12);
    EXPECT_NEAR(k.pose().theta_rad, 2.0 * plant::kPi, 1e-12);
}

}  // namespace
}  // namespace ddmr::hostsim
