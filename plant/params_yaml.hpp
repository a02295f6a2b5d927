#pragma once
// RobotParams <-> YAML (yaml-cpp). The file has one mapping per part
// (motor1, motor2, driver (the L298), tb6612, drv8833, l293d, l9110, battery,
// encoder1, encoder2, kinematics, integration), each with the keys of that part's field
// table. Keys left out keep their embedded default, so a file may override a
// few values only. An encoder's resolution is edges_per_motor_rev or
// edges_per_wheel_rev: the one a section gives replaces the other's default.
//
// Rejected, with one line naming the file, line:column, key and value:
// a missing or unreadable file, malformed YAML, an unknown section or key,
// a value of the wrong type, NaN/inf, a value outside its range, both
// resolution keys in one encoder section (naming both and their lines).

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>

#include "plant/robot_params.hpp"

namespace ddmr::plant {

/// A top-level key the plant loader refuses with a pointer to --board: the
/// wiring once lived in the plant file and is now a board file (hil/board.hpp).
inline constexpr const char* kBoardSection = "board";

/// Error in a parameter file; what() is a single line.
class ParamsFileError : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// Reads and validates a parameter file over the embedded defaults.
RobotParams load_robot_params(const std::filesystem::path& path);

/// Same, from text; `source` names it in messages.
RobotParams parse_robot_params(std::string_view yaml_text, const std::string& source);

/// Every parameter as YAML, doubles with 17 significant digits (exact round trip).
std::string emit_robot_params(const RobotParams& p);

/// Writes emit_robot_params(p) to `path`; throws ParamsFileError on failure.
void save_robot_params(const RobotParams& p, const std::filesystem::path& path);

}  // namespace ddmr::plant
