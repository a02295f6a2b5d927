#pragma once
// The robot's body against the world's walls (docs/world.md, "Body and
// contact"). The chassis is a rectangle in the robot's frame (origin at the
// middle of the wheel axle, x forward): from -rear_m to front_m along x and
// width_m across. The robot cannot pass through a wall: a step that would
// put a wall inside the rectangle is undone (Robot::step), the robot stops
// where it was, and the wheels then either
//   stall (slip_at_contact = 0, the default): the shafts are held while the
//         drive pushes the body into the wall: stall current, no encoder
//         edges; a drive that pulls the body off the wall frees them;
//   slip  (slip_at_contact = 1): the wheels keep turning on the floor, the
//         encoders keep counting, the body stays.
// The body does not slide along the wall or pivot about the contact (no
// friction model); walls have no height here (a kerb stops it too).
// Pure functions of plain types; SI units.

#include <Eigen/Core>

#include <array>
#include <optional>

#include "plant/diff_drive_kinematics.hpp"
#include "plant/param_spec.hpp"
#include "plant/world.hpp"

namespace ddmr::plant {

struct BodyParams {
    double front_m = 0.09;  ///< axle to the front edge [m] (an estimate for a kit chassis)
    double rear_m = 0.06;   ///< axle to the rear edge [m]
    double width_m = 0.16;  ///< across, the wheels included [m] (128 mm track + tyres)
    int slip_at_contact = 0;  ///< 0: the wheels stall against a wall; 1: they slip
};

const std::array<Field<BodyParams>, 4>& body_fields();
void validate(const BodyParams& p, const char* prefix);

/// Where the body touches a wall.
struct WallContact {
    std::size_t wall = 0;                             ///< index in World::walls
    Eigen::Vector2d point_m = Eigen::Vector2d::Zero();  ///< the middle of the wall's part inside the body
    Eigen::Vector2d normal = Eigen::Vector2d::Zero();   ///< unit, from the wall toward the body's axle middle
};

/// The first wall (in file order) that lies inside the body at `pose`, or none.
std::optional<WallContact> body_contact(const World& world, const BodyParams& body, const Pose& pose);

/// Whether a body moving at `v` (forward speed, turn rate) at `pose` moves
/// its contact point away from the wall.
bool moves_off(const WallContact& contact, const Pose& pose, const BodyVelocity& v);

}  // namespace ddmr::plant
