#pragma once
// `ddmr-hil sim`: the host reference simulation (tools/hostsim/), the
// thesis's closed-loop simulator on the HIL's plant model, as the ideal model
// or the firmware model or the ideal model with chosen fidelity switches.
// Writes DIR/sim.csv (1 kHz: truth.csv's columns, the drive, the goal and
// eq. 15), DIR/eeprom_log.csv (when the run writes a position log) and
// DIR/summary.json. See docs/hostsim.md.
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_sim_command(CLI::App& app);

}  // namespace ddmr::tools
