#pragma once
// `ddmr-hil report DIR`: the plots and report.md of a `run`, `profile` or
// `sim` output folder, of a `scenario` output folder (a report per scenario
// sub-folder and an index) or of one scenario's sub-folder
// (tools/report/make_report.py), made with Debian's python3
// (/usr/bin/python3) and its python3-matplotlib whatever `python3` comes
// first on PATH, or one line saying what to install. Another command's
// folder is refused in one line naming what it is (exit 2).
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_report_command(CLI::App& app);

}  // namespace ddmr::tools
