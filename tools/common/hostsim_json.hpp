#pragma once
// The host simulation's inputs as JSON, shared by `sim` and `sweep`.
#include <nlohmann/json.hpp>

#include "tools/hostsim/goal_trajectory.hpp"
#include "tools/hostsim/kanayama.hpp"

namespace ddmr::tools {

nlohmann::json gains_json(const hostsim::Gains& g);
nlohmann::json case_json(const hostsim::CaseSpec& c);

}  // namespace ddmr::tools
