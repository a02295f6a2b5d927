#pragma once
// world.json: the world a run drove in, for the report's plots (the report
// draws the tape lines and the walls under the robot's path). Lines are
// their centrelines as polylines (arcs sampled every 2 degrees, at least 8
// points), with width and reflectance; walls are segments with their height
// and obstacle name, where they stood at the end of the run (after any
// move-obstacle). Byte-identical for the same world (fixed precision).
#include <nlohmann/json.hpp>

#include "plant/world.hpp"

namespace ddmr::tools {

nlohmann::ordered_json world_json(const plant::World& world);

}  // namespace ddmr::tools
