// The body against the walls (plant/body_contact.hpp, Robot's contact), each
// number worked out by hand.
#include "plant/body_contact.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/robot.hpp"
#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

/// A wall across the x axis at `x_m`, 2 m long.
World wall_at_x(double x_m) {
    World w;
    w.walls.push_back(Wall{{x_m, -1.0}, {x_m, 1.0}, 0.2});
    return w;
}

TEST(BodyContact, TheFootprintTouchesAWallOnlyWhenItReachesIt) {
    const World w = wall_at_x(0.2);
    const BodyParams body;  // 0.09 m ahead of the axle, 0.06 behind, 0.16 wide
    EXPECT_FALSE(body_contact(w, body, Pose{0.10, 0.0, 0.0}).has_value());  // front edge at 0.19
    const std::optional<WallContact> c = body_contact(w, body, Pose{0.12, 0.0, 0.0});  // front at 0.21
    ASSERT_TRUE(c.has_value());
    EXPECT_NEAR(c->point_m.x(), 0.2, 1e-12);
    EXPECT_NEAR(c->point_m.y(), 0.0, 1e-12);  // the middle of the wall's part across the body (-0.08..0.08)
    EXPECT_NEAR(c->normal.x(), -1.0, 1e-12);  // toward the robot
    // Turned 90 degrees, the body is 0.16 m across x: its side at 0.08 + 0.12 = 0.20 just touches.
    EXPECT_TRUE(body_contact(w, body, Pose{0.125, 0.0, kPi / 2}).has_value());
    EXPECT_FALSE(body_contact(w, body, Pose{0.115, 0.0, kPi / 2}).has_value());
    // Backing into it: the rear edge 0.06 m behind the axle.
    EXPECT_TRUE(body_contact(w, body, Pose{0.25, 0.0, 0.0}).has_value());
    EXPECT_FALSE(body_contact(w, body, Pose{0.27, 0.0, 0.0}).has_value());
}

TEST(BodyContact, ADriveMovesOffTheWallOnlyAwayFromIt) {
    const WallContact c{0, {0.2, 0.0}, {-1.0, 0.0}};
    const Pose at{0.11, 0.0, 0.0};
    EXPECT_FALSE(moves_off(c, at, BodyVelocity{0.5, 0.0}));   // into the wall
    EXPECT_TRUE(moves_off(c, at, BodyVelocity{-0.5, 0.0}));   // backing away
    EXPECT_FALSE(moves_off(c, at, BodyVelocity{0.0, 1.0}));   // turning on the spot: the point moves along it
}

/// Both motors forward at full drive, 1 ms steps, for `seconds`.
void drive(Robot& r, double seconds, bool forward = true) {
    RobotInput in;
    in.mode = DriveMode::averaged;
    for (BridgeInput& b : in.bridge) {
        b.duty = 1.0;
        b.forward = forward;
    }
    r.set_input(in);
    EdgeBuffer e;
    for (long k = 0; k < std::lround(seconds / 1e-3); ++k) {
        e.clear();
        ASSERT_EQ(r.step(1e-3, e).status, StepStatus::ok);
    }
}

TEST(RobotContact, AWallStopsTheRobotAtTheWallAndItsWheelsStall) {
    const World w = wall_at_x(0.5);
    Robot r;
    r.set_world(&w);
    drive(r, 2.0);  // ~0.7 m/s: it reaches the wall in under a second
    // Stopped with its foremost front corner (0.09 m ahead of the axle,
    // 0.08 m to the side; the robot has turned a little) at the wall, within
    // one 1 ms step of travel (0.7 mm).
    const double th = r.pose().theta_rad;
    const double front = r.pose().x_m + 0.09 * std::cos(th) + 0.08 * std::fabs(std::sin(th));
    EXPECT_LT(front, 0.5);
    EXPECT_GT(front, 0.5 - 0.0008);
    EXPECT_TRUE(r.in_contact());
    ASSERT_EQ(r.contact_count(), 1U);
    const ContactEvent& e = r.contacts().front();
    EXPECT_NEAR(e.x_m, 0.5, 1e-12);
    // The first touch is at the foremost corner: the right one, the robot
    // having turned a little to the left (the right motor is faster).
    EXPECT_GT(th, 0.0);
    EXPECT_LT(e.y_m, r.pose().y_m - 0.05);
    EXPECT_GT(e.y_m, r.pose().y_m - 0.081);
    EXPECT_GT(e.speed_m_s, 0.5);  // it hit the wall at speed
    EXPECT_LT(e.t_s, 1.2);
    // Stalled: no rotation, no edges, the stall current V / R (6.1 V less the
    // bridge's drop, over ~5.3 ohm: about 1 A).
    const std::uint64_t edges = r.edge_count(0) + r.edge_count(1);
    drive(r, 0.5);
    EXPECT_EQ(r.edge_count(0) + r.edge_count(1), edges);
    EXPECT_EQ(r.wheel_speed_rad_s(0), 0.0);
    EXPECT_GT(r.motor_current_A(0), 0.7);
    EXPECT_LT(r.motor_current_A(0), 1.2);
    // Reversing frees the wheels: the robot backs away.
    drive(r, 0.5, false);
    EXPECT_FALSE(r.in_contact());
    EXPECT_LT(r.pose().x_m, 0.5 - 0.09 - 0.1);
    EXPECT_EQ(r.contact_count(), 1U);
}

TEST(RobotContact, WithSlipAtContactTheWheelsTurnOnAndTheEncodersCount) {
    const World w = wall_at_x(0.5);
    RobotParams p = default_robot_params();
    p.body.slip_at_contact = 1;
    Robot r(p);
    r.set_world(&w);
    drive(r, 2.0);
    EXPECT_TRUE(r.in_contact());
    const double x = r.pose().x_m;
    const std::uint64_t edges = r.edge_count(0);
    drive(r, 0.5);
    EXPECT_EQ(r.pose().x_m, x);                 // the body stays
    EXPECT_GT(r.edge_count(0), edges + 100);    // the wheels spin on: ~22 rad/s x 384 edges a turn
    EXPECT_GT(r.wheel_speed_rad_s(0), 15.0);
}

TEST(RobotContact, WithoutWallsNothingChanges) {
    Robot a, b;
    const World none;
    b.set_world(&none);
    drive(a, 1.0);
    drive(b, 1.0);
    EXPECT_EQ(a.pose().x_m, b.pose().x_m);
    EXPECT_EQ(a.edge_count(0), b.edge_count(0));
}

}  // namespace
}  // namespace ddmr::plant
