#pragma once
// StepFailed: a scenario step that did not hold (thrown by the step, caught
// by the runner, which ends the scenario with its verdict and message).

#include <string>

#include "scenario/scenario_runner.hpp"

namespace ddmr::tools::scenario {

struct StepFailed {
    Verdict verdict;
    std::string message;
};

/// `s` with \r, \n and other control or non-ASCII bytes escaped.
std::string printable(const std::string& s);

}  // namespace ddmr::tools::scenario
