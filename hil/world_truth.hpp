#pragma once
// The robot in its world, as truth.csv's columns and scenario signals
// (docs/world.md, "Truth columns"):
//   line_offset_m    the nearest line's centreline across the robot's
//                    heading, from the middle of the wheel axle, positive to
//                    the left (a world with lines only);
//   wall_distance_m  the nearest wall from the middle of the wheel axle (a
//                    world with walls only);
//   contact          1 while the body rests against a wall, else 0 (walls only);
//   contacts         the contacts begun so far (walls only).
// A world without lines or walls adds no columns: the plain floor's
// truth.csv is what it was before worlds.

#include <string>
#include <vector>

#include "plant/robot.hpp"
#include "plant/world.hpp"

namespace ddmr::hil {

class WorldTruth {
public:
    /// `world` and `robot` must outlive this; the robot is read at each values().
    WorldTruth(const plant::World& world, const plant::Robot& robot);

    [[nodiscard]] const std::vector<std::string>& columns() const { return columns_; }
    /// Appends one value per column, at the pose now.
    void values(std::vector<double>& out) const;

private:
    const plant::World& world_;
    const plant::Robot& robot_;
    std::vector<std::string> columns_;
};

}  // namespace ddmr::hil
