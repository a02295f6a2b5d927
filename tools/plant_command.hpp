#pragma once
// `ddmr-hil plant`: open-loop run of the plant model (plant/) with constant
// inputs. Writes DIR/plant.csv (1 kHz samples) and DIR/summary.json.
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_plant_command(CLI::App& app);

}  // namespace ddmr::tools
