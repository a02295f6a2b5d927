#pragma once
// `ddmr-hil scenario` run as a user runs it, for the tests of the scenario
// front end: write scenario files into a test's folder, run the command,
// read what a scenario's worker wrote.
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {

/// Writes `text` to `dir`/`name` and returns the path.
inline std::filesystem::path write_text(const TempDir& dir, const std::string& name, const std::string& text) {
    auto p = dir / name;  // not const: returned by move
    std::ofstream(p) << text;
    return p;
}

/// `ddmr-hil scenario ARGS`.
inline ProcessResult scenario(const std::string& args) {
    return run_command(sh_quote(cli_path().string()) + " scenario " + args);
}

/// A scenario's result.json, in its output folder `dir` (--out's DIR/<name>).
inline nlohmann::json result_of(const std::filesystem::path& dir) {
    return nlohmann::json::parse(read_text(dir / "result.json"));
}

}  // namespace ddmr::test
