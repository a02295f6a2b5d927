// ddmr-hil: command-line front end. Each subcommand lives in its own file and
// registers itself on the CLI11 app; main only dispatches and maps errors to
// exit codes (exit_codes.hpp).
#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>
#include <vector>

#include "exit_codes.hpp"
#include "calibrate_command.hpp"
#include "report_command.hpp"
#include "compare_command.hpp"
#include "merge_command.hpp"
#include "parts_command.hpp"
#include "plant_command.hpp"
#include "run_command.hpp"
#include "scenario_command.hpp"
#include "sim_command.hpp"
#include "sweep_command.hpp"

int main(int argc, char** argv) {
    CLI::App app{"ddmr-hil: run the unmodified differential-drive robot firmware in simavr, "
                 "closed-loop with a plant model"};
    app.require_subcommand(1);
    app.set_version_flag("--version", "ddmr-hil 0.1.0");
    const std::vector<ddmr::tools::Subcommand> subcommands = {
        ddmr::tools::register_run_command(app),
        ddmr::tools::register_profile_command(app),
        ddmr::tools::register_compare_command(app),
        ddmr::tools::register_plant_command(app),
        ddmr::tools::register_sim_command(app),
        ddmr::tools::register_sweep_command(app),
        ddmr::tools::register_scenario_command(app),
        ddmr::tools::register_merge_command(app),
        ddmr::tools::register_calibrate_command(app),
        ddmr::tools::register_report_command(app),
        ddmr::tools::register_parts_command(app),
    };
    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line, naming the option and the value (CLI11's own message).
        std::fprintf(stderr, "ddmr-hil: error: %s (see --help)\n", e.what());
        return ddmr::tools::kExitBadInput;
    }
    for (const auto& sub : subcommands) {
        if (!sub.app->parsed()) continue;
        try {
            return sub.run();
        } catch (const std::exception& e) {
            std::fprintf(stderr, "ddmr-hil %s: error: %s\n", sub.app->get_name().c_str(), e.what());
            return ddmr::tools::kExitBadInput;
        }
    }
    return ddmr::tools::kExitBadInput;
}
