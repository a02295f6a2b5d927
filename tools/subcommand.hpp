#pragma once
// A subcommand of ddmr-hil: the CLI11 sub-app it registered and the action
// that runs it after parsing. The action returns the process exit code
// (see exit_codes.hpp) and may throw for bad input (mapped to exit code 2).
#include <CLI/CLI.hpp>

#include <functional>

namespace ddmr::tools {

struct Subcommand {
    CLI::App* app = nullptr;
    std::function<int()> run;
};

}  // namespace ddmr::tools
