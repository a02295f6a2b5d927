#pragma once
// `ddmr-hil calibrate LOG... [--case N] [--fit KEY,...] [--hold-out LOG]...
//                    [--split F] [--plant FILE] [--out DIR] [--seed N] ...`:
// fits plant parameters to a real robot's serial dumps (the reference
// sketch's report and EEPROM dump) by re-simulating the closed loop with the
// host simulation's firmware model, reports what the logs can and cannot pin
// down, judges the fit on what it was not fitted on, and confirms it in the
// full HIL with the real firmware (tools/calibrate/, docs/calibration.md).
//
// Writes DIR/plant.yaml (loadable with --plant: every parameter, the fitted
// ones with their 95 % interval and the logs in a comment), DIR/calibration.json,
// DIR/report.md with DIR/xy_*.svg (logged, before and after tracks),
// DIR/tracks.csv and, unless --no-hil, DIR/hil/ (the HIL run on the fitted plant).
// Exit 0 on success, 2 for bad input (a --fit parameter the logs cannot see
// included), 3 when the HIL confirmation's firmware run fails.
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_calibrate_command(CLI::App& app);

}  // namespace ddmr::tools
