#pragma once
// `ddmr-hil compare RUN_DIR`: the HIL run against the host simulation of the
// same robot. Exit 0 within tolerance, 1 not, 2 on error.
#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_compare_command(CLI::App& app);

}  // namespace ddmr::tools
