#include "report_command.hpp"

#include <sys/wait.h>

#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <string>

#include "common/output_folder.hpp"
#include "common/spawn.hpp"
#include "exit_codes.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;

/// Debian's interpreter, where python3-matplotlib installs: not PATH's first python3.
constexpr const char* kPython = "/usr/bin/python3";

/// Runs args with this process's stdout and stderr; its exit status (-1 if it died).
int run_inherited(const std::vector<std::string>& args) {
    pid_t pid = 0;
    const int rc = spawn_inherit(args, pid);
    if (rc != 0) throw std::runtime_error(fmt::format("cannot start {}: {}", args[0], std::strerror(rc)));
    int status = 0;
    if (waitpid(pid, &status, 0) < 0) throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The folders make_report.py plots: a run's (or profile's), a sim's, a
/// scenario suite's (a report per scenario and an index) and one scenario's.
bool reportable(FolderKind kind) {
    return kind == FolderKind::run || kind == FolderKind::sim || kind == FolderKind::scenario ||
           kind == FolderKind::scenario_result;
}

int run_report(const std::string& dir) {
    const FolderKind kind = folder_kind(dir);
    if (!reportable(kind)) {
        throw std::invalid_argument(fmt::format("{}: {}; report takes the output folder of `ddmr-hil run`, `profile`, "
                                                "`sim` or `scenario` (or one scenario's sub-folder){}",
                                                dir, describe(kind),
                                                kind == FolderKind::calibrate ? " (a calibration writes its own report.md)"
                                                : kind == FolderKind::sweep   ? " (a sweep plots its own figures)"
                                                                              : ""));
    }
    if (!fs::is_regular_file(kPython)) {
        throw std::runtime_error(fmt::format("{} is missing: apt-get install python3 python3-matplotlib", kPython));
    }
    if (run_inherited({kPython, "-c", "import matplotlib"}) != 0) {
        throw std::runtime_error(fmt::format("{} has no matplotlib (the message above): apt-get install "
                                             "python3-matplotlib",
                                             kPython));
    }
    const int rc = run_inherited({kPython, DDMR_REPORT_SCRIPT, dir});
    if (rc != 0) {
        std::fprintf(stderr, "ddmr-hil report: the report script failed (exit %d)\n", rc);
        return rc == kExitBadInput ? kExitBadInput : kExitFirmware;
    }
    return kExitOk;
}

}  // namespace

Subcommand register_report_command(CLI::App& app) {
    auto dir = std::make_shared<std::string>();
    CLI::App* sub = app.add_subcommand(
        "report",
        "Plot a run, profile, sim or scenario output folder and write its report.md (X-Y, tracking error, wheel "
        "speeds, drive, currents and battery as PWM-window means; a scenario's steps and verdicts, a suite's index) "
        "with Debian's python3-matplotlib");
    sub->add_option("DIR", *dir,
                    "A folder written by `ddmr-hil run` or `profile` (and `compare`), `sim`, or `scenario` (the suite: "
                    "a report per scenario and an index; or one scenario's sub-folder)")
        ->required();
    return {sub, [dir] { return run_report(*dir); }};
}

}  // namespace ddmr::tools
