#pragma once
// The combined result of a scenario suite, shared by `ddmr-hil scenario`
// (whole or one shard) and `ddmr-hil merge` (shards combined), so a merged
// run's results.json is byte-identical to an unsharded run's.
//
// Folder layout of a suite run:
//   results.json      every scenario in the suite's order: name, file,
//                     verdict, message, simulated seconds; passed/total
//   shard.json        (only with --shard I/N) the shard and the whole suite's
//                     scenario names in order, for `merge` to check coverage
//   <name>/           one folder per scenario (result.json, uart.txt, ...)

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/scenario_runner.hpp"

namespace ddmr::tools::scenario {

/// `--shard I/N`: the I-th (1-based) of N round-robin slices of the suite.
struct Shard {
    unsigned index = 1;  ///< 1..count
    unsigned count = 1;
    /// True if the scenario at `position` (0-based, in the suite's order) is in this shard.
    bool contains(std::size_t position) const { return position % count == index - 1; }
    std::string text() const { return std::to_string(index) + "/" + std::to_string(count); }
};
/// Parses "I/N" (1 <= I <= N <= 100000); throws std::invalid_argument naming the text.
Shard parse_shard(const std::string& text);

/// A scenario's result as its worker left it in `dir`/result.json.
/// Throws std::runtime_error if the file is missing or malformed.
ScenarioResult read_scenario_result(const std::filesystem::path& dir);

/// results.json of `results` (in the suite's order): deterministic, no wall times.
nlohmann::json suite_results_json(const std::vector<ScenarioResult>& results);

/// The process exit code of a suite: 3 if any firmware failure, else 1 if
/// any failed check, else 0.
int suite_exit_code(const std::vector<ScenarioResult>& results);

/// One line per scenario (and per failure) on stdout, then the count.
void print_verdicts(const std::vector<ScenarioResult>& results);

/// The end of a suite run, the same for `scenario` and `merge`: the verdicts
/// on stdout (print_verdicts), `out_dir`/results.json, JUnit XML at
/// `junit_path` unless it is empty; returns the process exit code
/// (suite_exit_code). `out_dir` must exist.
int finish_suite(const std::vector<ScenarioResult>& results, const std::filesystem::path& out_dir,
                 const std::filesystem::path& junit_path);

}  // namespace ddmr::tools::scenario
