#pragma once
// What kind of ddmr-hil output folder a path is, from the files each command
// writes, so a command given the wrong folder can say what it got and what it
// expected in one line (issue 19): `run`/`profile` (summary.json with
// clock_hz), `sim` (summary.json with model and fidelity), `scenario`
// (results.json), one scenario's sub-folder of it (result.json), `sweep`
// (sweep.json), `calibrate` (calibration.json).
#include <filesystem>
#include <string>

namespace ddmr::tools {

enum class FolderKind { missing, not_a_folder, run, sim, scenario, scenario_result, sweep, calibrate, other };

FolderKind folder_kind(const std::filesystem::path& dir);

/// "a `ddmr-hil sim` output folder", "not a folder", "a folder without any
/// ddmr-hil output (no run's summary.json, results.json, result.json,
/// sweep.json or calibration.json)", ... for messages.
std::string describe(FolderKind kind);

}  // namespace ddmr::tools
