#pragma once
// `ddmr-hil merge` of `ddmr-hil sweep --shard I/N` folders: checks that they
// are the N shards of one sweep, each once, then writes the folder an
// unsharded `sweep --no-plot` writes (every study CSV and sweep.json, byte
// for byte; tools/sweep_results.hpp). The plots are not drawn: run
// tools/report/plot_sweep.py on the merged folder for them.

#include <filesystem>
#include <string>
#include <vector>

namespace ddmr::tools {

/// True if the folders are sweep shards (the first one's shard.json says
/// so): `merge` then calls merge_sweep_shards instead of merging scenarios.
bool are_sweep_shards(const std::vector<std::string>& shard_dirs);

/// Merges; returns the sweep's exit code (0, or 1 if a plant stopped early
/// in some run). Throws std::invalid_argument / std::runtime_error naming
/// the folder for shards that do not belong together, before writing.
int merge_sweep_shards(const std::vector<std::string>& shard_dirs, const std::filesystem::path& out_dir);

}  // namespace ddmr::tools
