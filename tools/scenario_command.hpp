#pragma once
// `ddmr-hil scenario FILE.yaml...`: firmware regression tests in AVR time
// (tools/scenario/), run in parallel worker processes, one combined verdict,
// JUnit XML for CI.
#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_scenario_command(CLI::App& app);

}  // namespace ddmr::tools
