#pragma once
// `ddmr-hil sweep`: the thesis's gain sensitivity studies (ch. 5, figs. 5-2
// to 5-8, appendix A2) on the host simulation (tools/hostsim/gain_sweep.hpp),
// every run in parallel on a fixed pool of threads. Writes DIR/<study>.csv
// (long format, 100 Hz), DIR/sweep.json (per run: final, RMS and max
// tracking error, settling time) and, through tools/report/plot_sweep.py,
// DIR/<study>.png and .svg. Same options, same bytes, whatever -j.
// See docs/hostsim.md, "Sweep".
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_sweep_command(CLI::App& app);

}  // namespace ddmr::tools
