#include "common/plant_option.hpp"

#include <fmt/format.h>

#include <filesystem>
#include <stdexcept>

#include "plant/params_yaml.hpp"

namespace ddmr::tools {

PlantChoice resolve_plant_option(const std::string& value) {
    PlantChoice c;
    c.kinematic = value == kKinematicPlant;
    if (value.empty() || c.kinematic) {
        c.params = plant::default_robot_params();
        c.source = c.kinematic ? kKinematicPlant : "(embedded defaults)";
        return c;
    }
    if (!std::filesystem::is_regular_file(value)) {
        throw std::invalid_argument(fmt::format("--plant {}: no such file (a plant YAML, or 'kinematic')", value));
    }
    c.params = plant::load_robot_params(value);
    c.source = value;
    return c;
}

}  // namespace ddmr::tools
