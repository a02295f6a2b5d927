#pragma once
// The check every merge of `--shard I/N` folders makes before it writes:
// the folders are the N shards of one split, each exactly once.

#include <string>
#include <vector>

#include "scenario/suite_results.hpp"

namespace ddmr::tools {

/// A shard's --out folder and the shard its shard.json names.
struct ShardFolder {
    std::string dir;
    scenario::Shard shard;
};

/// Throws std::invalid_argument naming the folder if `folders` is empty,
/// mixes splits (another N), repeats a shard, or misses one.
void check_shard_set(const std::vector<ShardFolder>& folders);

}  // namespace ddmr::tools
