#pragma once
// Where a sensor sits on the chassis (docs/world.md, "Sensors"): its board-file
// keys and the world point and direction it sees from at a robot pose.
// The robot's frame: origin at the middle of the wheel axle, x forward, y to
// the left, heading counter-clockwise from x (as the pose's theta).

#include <Eigen/Core>

#include <vector>

#include "hil/parts/part.hpp"

namespace ddmr::hil {

struct SensorMount {
    double x_m = 0.0;
    double y_m = 0.0;
    double heading_rad = 0.0;  ///< a directional sensor's axis (0: straight ahead)
};

/// The keys x_mm, y_mm and, with `directional`, heading_deg, each with `what`
/// in its description ("the spot's", "the transducers'").
std::vector<PartKey> mount_keys(const std::string& what, bool directional, double default_x_mm);
/// The mount an entry's keys give (heading 0 without heading_deg).
SensorMount mount_of(const PartContext& ctx, bool directional);

/// The mount's point in the world at robot pose `pose`.
Eigen::Vector2d world_point(const plant::Pose& pose, const SensorMount& mount);
/// The mount's axis in the world at robot pose `pose` [rad].
double world_heading_rad(const plant::Pose& pose, const SensorMount& mount);

}  // namespace ddmr::hil
