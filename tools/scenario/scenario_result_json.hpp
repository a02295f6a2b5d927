#pragma once
// A scenario's result.json (docs/scenarios.md, "Results"): its verdict, its
// steps with their cycles and messages, the firmware, board and serial set-up.
// Wall time is not in it (not deterministic): it goes to stdout.

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "scenario/scenario.hpp"
#include "scenario/scenario_runner.hpp"

namespace ddmr::tools::scenario {

/// result.json of scenario `s`, which ended as `r`, with the run's wiring warnings.
nlohmann::json scenario_result_json(const Scenario& s, const ScenarioResult& r,
                                    const std::vector<std::string>& wiring_warnings);

}  // namespace ddmr::tools::scenario
