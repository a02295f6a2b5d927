#pragma once
// The scenario steps as data (issue 19, item 9): each kind with the forms of
// its value, what it does, and a minimal example. The parser
// (scenario_yaml.cpp) accepts exactly these kinds; `ddmr-hil scenario
// --list-steps` prints them; docs/scenarios.md and
// docs/schema/scenario.schema.json describe each in full.
#include <string_view>
#include <vector>

namespace ddmr::tools::scenario {

struct StepInfo {
    std::string_view kind;     ///< "wait-serial"
    std::string_view forms;    ///< "\"text\" | {text, timeout}"
    std::string_view what;     ///< one line
    std::string_view example;  ///< a valid step line on the reference robot: "wait-serial: {text: END, timeout: 20s}"
};

/// Every step kind, in the order of docs/scenarios.md.
const std::vector<StepInfo>& step_catalog();

/// The kind's entry, or nullptr.
const StepInfo* find_step(std::string_view kind);

/// The catalogue as text: one block per step (kind, forms, what, example).
std::string_view step_catalog_text();

}  // namespace ddmr::tools::scenario
