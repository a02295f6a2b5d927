#include "common/output_folder.hpp"

#include <nlohmann/json.hpp>

#include <fstream>

namespace ddmr::tools {

namespace fs = std::filesystem;

FolderKind folder_kind(const fs::path& dir) {
    std::error_code ec;
    if (!fs::exists(dir, ec)) return FolderKind::missing;
    if (!fs::is_directory(dir, ec)) return FolderKind::not_a_folder;
    if (fs::is_regular_file(dir / "summary.json", ec)) {
        std::ifstream in(dir / "summary.json");
        const nlohmann::json j = nlohmann::json::parse(in, nullptr, false);
        if (j.is_object() && j.contains("clock_hz")) return FolderKind::run;
        if (j.is_object() && j.contains("model") && j.contains("fidelity")) return FolderKind::sim;
        return FolderKind::other;
    }
    if (fs::is_regular_file(dir / "results.json", ec)) return FolderKind::scenario;
    if (fs::is_regular_file(dir / "result.json", ec)) return FolderKind::scenario_result;
    if (fs::is_regular_file(dir / "sweep.json", ec)) return FolderKind::sweep;
    if (fs::is_regular_file(dir / "calibration.json", ec)) return FolderKind::calibrate;
    return FolderKind::other;
}

std::string describe(FolderKind kind) {
    switch (kind) {
        case FolderKind::missing: return "no such folder";
        case FolderKind::not_a_folder: return "not a folder";
        case FolderKind::run: return "a `ddmr-hil run` (or `profile`) output folder";
        case FolderKind::sim: return "a `ddmr-hil sim` output folder";
        case FolderKind::scenario: return "a `ddmr-hil scenario` output folder (one sub-folder per scenario)";
        case FolderKind::scenario_result: return "one scenario's folder of a `ddmr-hil scenario` output folder";
        case FolderKind::sweep: return "a `ddmr-hil sweep` output folder";
        case FolderKind::calibrate: return "a `ddmr-hil calibrate` output folder";
        case FolderKind::other: break;
    }
    return "a folder without ddmr-hil's outputs (no run's summary.json, results.json, result.json, sweep.json or "
           "calibration.json)";
}

}  // namespace ddmr::tools
