#pragma once
// A plant parameter by its file key ("motor1.resistance_ohm", the key a plant
// YAML file and a scenario's plant overrides use), for tools that vary
// parameters one by one (calibration, sensitivity studies). Only real-valued
// parameters: counts and seeds are not varied.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "plant/param_spec.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::plant {

struct ParamRef {
    std::string key;     ///< "motor1.resistance_ohm"
    double* value = nullptr;  ///< into the RobotParams it was found in
    Range range;         ///< the valid range (param_spec tables)
    const char* unit = "";
};

/// The real-valued parameter `key` of `p`, or nullopt (unknown key, or an
/// integer field such as encoder1.edges_per_motor_rev).
std::optional<ParamRef> find_param(RobotParams& p, std::string_view key);

/// Every real-valued parameter key, in file order.
std::vector<std::string> param_keys();

}  // namespace ddmr::plant
