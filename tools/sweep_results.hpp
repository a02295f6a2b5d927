#pragma once
// The files of a gain sweep, shared by `ddmr-hil sweep` (whole, or one
// `--shard I/N` slice of its runs) and `ddmr-hil merge` (the slices
// combined), so that a merged sweep's files are byte-identical to an
// unsharded sweep's: both write them with write_sweep_folder() from the same
// per-run records.
//
// Folder of a whole sweep (or of a merge):
//   <study id>.csv   one per study: kSweepCsvHeader, then every run's rows
//   sweep.json       the sweep's settings, each study and each run's metrics
//   <study id>.png, .svg  the plots (`sweep` only; tools/report/plot_sweep.py)
// Folder of one shard:
//   shard.json       {"shard": "I/N", "sweep": sweep.json without the runs,
//                     "run_study": the study index of every run of the whole
//                     sweep, in order}: merge checks that shards belong together
//   run-KKKK.json    the run's entry of sweep.json (K: its 1-based position in
//   run-KKKK.csv     the whole sweep) and its rows of the study's CSV, with
//                    the header; only for the runs of this shard

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scenario/suite_results.hpp"

namespace ddmr::tools {

/// First line of every study CSV and of every shard's run CSV.
inline constexpr const char* kSweepCsvHeader =
    "case,gain_value,t_s,x_m,y_m,theta_rad,goal_x_m,goal_y_m,error_m,xe_m,ye_m,v_m_s,omega_rad_s\n";

/// One run of a sweep, as its files hold it.
struct SweepRunRecord {
    std::size_t study = 0;     ///< index into the header's "studies"
    nlohmann::json summary;    ///< its entry in sweep.json's study "runs"
    std::string csv_rows;      ///< its rows of the study's CSV, without the header
};

/// The plant of the run stopped early (summary's "status" is not "ok").
bool stopped_early(const SweepRunRecord& r);

/// Writes every study's CSV and sweep.json into `dir` (atomically, each):
/// `header` is sweep.json with each study's "runs" empty, `records` every
/// run of the sweep in order.
void write_sweep_folder(const std::filesystem::path& dir, const nlohmann::json& header,
                        const std::vector<SweepRunRecord>& records);

/// The shard's part of a sweep: `records[k]` belongs to run k (0-based) of
/// the whole sweep and must be set exactly for the runs `shard` contains;
/// `run_study` is the study index of every run of the whole sweep.
struct SweepShard {
    scenario::Shard shard;
    nlohmann::json header;
    std::vector<std::size_t> run_study;
};
void write_sweep_shard(const std::filesystem::path& dir, const SweepShard& s,
                       const std::vector<const SweepRunRecord*>& records);

/// True if `dir` holds the shard.json of a sweep shard (not a scenario shard).
bool is_sweep_shard(const std::filesystem::path& dir);
/// Reads a sweep shard's shard.json; throws std::runtime_error naming the file.
SweepShard read_sweep_shard(const std::filesystem::path& dir);
/// Reads run k (0-based) of the whole sweep from the shard folder holding it.
SweepRunRecord read_sweep_run(const std::filesystem::path& dir, std::size_t k, std::size_t study);

}  // namespace ddmr::tools
