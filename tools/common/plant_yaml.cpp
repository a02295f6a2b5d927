#include "common/plant_yaml.hpp"

#include <string>

#include "plant/params_yaml.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::tools {

YAML::Node default_plant_yaml() { return YAML::Load(plant::emit_robot_params(plant::default_robot_params())); }

void merge_plant_yaml(YAML::Node base, const YAML::Node& over) {
    for (const char* key : {"edges_per_motor_rev", "edges_per_wheel_rev"}) {
        const std::string other =
            std::string(key) == "edges_per_motor_rev" ? "edges_per_wheel_rev" : "edges_per_motor_rev";
        if (over.IsMap() && over[key] && base.IsMap() && base[other]) base.remove(other);
    }
    for (const auto& kv : over) {
        const std::string k = kv.first.Scalar();
        if (kv.second.IsMap() && base[k] && base[k].IsMap()) {
            merge_plant_yaml(base[k], kv.second);
        } else {
            base[k] = YAML::Clone(kv.second);
        }
    }
}

void seed_plant_yaml(YAML::Node& plant, uint64_t seed) {
    for (const char* enc : {"encoder1", "encoder2"}) {
        if (!plant[enc]) plant[enc] = YAML::Node(YAML::NodeType::Map);
        plant[enc]["seed"] = seed + (std::string(enc) == "encoder1" ? 0 : 1);
    }
}

}  // namespace ddmr::tools
