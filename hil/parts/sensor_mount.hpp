#pragma once
// Where a sensor sits on the chassis (docs/world.md, "Sensors"): its board-file
// keys and the world point and direction it sees from at a robot pose.
// The robot's frame: origin at the middle of the wheel axle, x forward, y to
// the left, heading counter-clockwise from x (as the pose's theta).

#include <Eigen/Core>

#include <optional>
#include <vector>

#include "hil/parts/part.hpp"

namespace ddmr::hil {

/// The keys x_mm, y_mm and, with `directional`, heading_deg and `mount` (a
/// servo it sits on), each with `what` in its description ("the spot's",
/// "the transducers'").
std::vector<PartKey> mount_keys(const std::string& what, bool directional, double default_x_mm);
/// The mount an entry's keys give (heading 0 without heading_deg).
SensorMount mount_of(const PartContext& ctx, bool directional);
/// A directional entry with `mount` and its own x_mm, y_mm or heading_deg
/// too: refused (on a servo, the horn sets where the sensor is).
std::optional<PartKeyProblem> check_mount(const PartEntry& e);

/// Where a directional sensor is at run time: fixed on the chassis (its
/// x_mm, y_mm, heading_deg), or on the horn of the servo its `mount` key
/// names, turning with it.
class SensorPlacement {
public:
    explicit SensorPlacement(const PartContext& ctx);
    /// The mount at AVR cycle `cycle` (a servo's angle then).
    [[nodiscard]] SensorMount at(Cycles cycle) const {
        if (carrier_ == nullptr) return fixed_;
        return carrier_->carried_mount(cycle).value_or(fixed_);
    }

private:
    SensorMount fixed_;
    const Part* carrier_ = nullptr;
};

/// The mount's point in the world at robot pose `pose`.
Eigen::Vector2d world_point(const plant::Pose& pose, const SensorMount& mount);
/// The mount's axis in the world at robot pose `pose` [rad].
double world_heading_rad(const plant::Pose& pose, const SensorMount& mount);

}  // namespace ddmr::hil
