#pragma once
// JUnit XML of a scenario suite (pugixml), the format CI systems display:
// one <testsuite> with a <testcase> per scenario; a failed check is a
// <failure>, a firmware crash or timeout an <error>; the step log goes to
// <system-out>. Times are wall seconds (the only non-deterministic values).

#include <filesystem>
#include <string>
#include <vector>

#include "scenario/scenario_runner.hpp"

namespace ddmr::tools::scenario {

/// The XML document as text.
std::string junit_xml(const std::string& suite_name, const std::vector<ScenarioResult>& results);

}  // namespace ddmr::tools::scenario
