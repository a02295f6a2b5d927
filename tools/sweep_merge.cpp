#include "sweep_merge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "exit_codes.hpp"
#include "shard_set.hpp"
#include "sweep_results.hpp"
#include "tools/hostsim/gain_sweep.hpp"

namespace ddmr::tools {
namespace fs = std::filesystem;

bool are_sweep_shards(const std::vector<std::string>& shard_dirs) {
    return !shard_dirs.empty() && is_sweep_shard(shard_dirs.front());
}

int merge_sweep_shards(const std::vector<std::string>& shard_dirs, const fs::path& out_dir) {
    // Check that the shards are one sweep, each shard once, before writing.
    std::vector<SweepShard> shards;
    std::vector<ShardFolder> folders;
    for (const auto& d : shard_dirs) {
        if (!is_sweep_shard(d)) throw std::invalid_argument(fmt::format("{}: not a `sweep --shard` folder", d));
        shards.push_back(read_sweep_shard(d));
        const SweepShard& s = shards.back();
        if (s.header != shards.front().header || s.run_study != shards.front().run_study) {
            throw std::invalid_argument(fmt::format("{}: a shard of another sweep (its settings or studies differ)", d));
        }
        folders.push_back({d, s.shard});
    }
    check_shard_set(folders);
    const SweepShard& sweep = shards.front();
    std::vector<SweepRunRecord> records;
    for (std::size_t k = 0; k < sweep.run_study.size(); ++k) {
        const auto holder = std::find_if(folders.begin(), folders.end(),
                                         [k](const ShardFolder& f) { return f.shard.contains(k); });
        records.push_back(read_sweep_run(holder->dir, k, sweep.run_study[k]));
    }
    prepare_output_dir(out_dir);
    write_sweep_folder(out_dir, sweep.header, records);
    fmt::print("merge: {} sweep shards, {} studies, {} runs, wrote {} (no plots: `{} {}` draws them)\n",
               shards.size(), sweep.header.at("studies").size(), records.size(), out_dir.string(),
               hostsim::sweep_plot_script(), out_dir.string());
    if (std::any_of(records.begin(), records.end(), stopped_early)) {
        fmt::print(stderr, "ddmr-hil merge: a plant stopped early in some runs (status in sweep.json)\n");
        return kExitCheckFailed;
    }
    return kExitOk;
}

}  // namespace ddmr::tools
