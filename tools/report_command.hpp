#pragma once
// `ddmr-hil report RUN_DIR`: the plots and report.md of a `run` or `profile`
// output folder (tools/report/make_report.py), made with Debian's python3
// (/usr/bin/python3) and its python3-matplotlib whatever `python3` comes
// first on PATH, or one line saying what to install.
#include <CLI/CLI.hpp>

#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_report_command(CLI::App& app);

}  // namespace ddmr::tools
