#pragma once
// The world file (docs/world.md; schema docs/schema/world.schema.json): the
// floor, its tape lines, the walls and the robot's start pose, read into a
// plant::World. Every refusal names the place and the key:
// "FILE:LINE: key 'K': what is wrong" (std::runtime_error), as the board
// file's do: an unknown key, a line with no width, a wall of zero length, a
// polygon of fewer than 3 corners, an arc of no radius or no turn.

#include <filesystem>

#include "plant/world.hpp"

namespace ddmr::hil {

/// Reads and checks a world file.
plant::World load_world_file(const std::filesystem::path& path);

}  // namespace ddmr::hil
