#pragma once
// `ddmr-hil run`: boot the firmware in simavr, send the case byte, record.
#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_run_command(CLI::App& app);
/// `ddmr-hil profile`: `run` with --profile on, same options.
Subcommand register_profile_command(CLI::App& app);

}  // namespace ddmr::tools
