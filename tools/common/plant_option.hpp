#pragma once
// The `--plant` option of `sim` and `sweep`: empty (the embedded defaults),
// "kinematic" (wheel speeds follow the command instantly), or a plant YAML.
#include <string>

#include "plant/robot_params.hpp"

namespace ddmr::tools {

inline constexpr const char* kKinematicPlant = "kinematic";

struct PlantChoice {
    plant::RobotParams params;  ///< the defaults for "" and "kinematic"
    bool kinematic = false;
    std::string source;         ///< for summary.json
};

/// Throws std::invalid_argument naming the option and the file when a YAML
/// path does not exist; plant::ParamsFileError for a bad file.
PlantChoice resolve_plant_option(const std::string& value);

}  // namespace ddmr::tools
