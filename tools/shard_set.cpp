#include "shard_set.hpp"

#include <fmt/format.h>

#include <set>
#include <stdexcept>

namespace ddmr::tools {

void check_shard_set(const std::vector<ShardFolder>& folders) {
    if (folders.empty()) throw std::invalid_argument("give the shards' folders");
    const unsigned count = folders.front().shard.count;
    std::set<unsigned> seen;
    for (const auto& [dir, s] : folders) {
        if (s.count != count) {
            throw std::invalid_argument(fmt::format("{}: shard {} of a {}-way split, not {}", dir, s.text(), s.count, count));
        }
        if (!seen.insert(s.index).second) throw std::invalid_argument(fmt::format("{}: shard {} given twice", dir, s.text()));
    }
    for (unsigned i = 1; i <= count; ++i) {
        if (!seen.count(i)) throw std::invalid_argument(fmt::format("shard {}/{} is missing", i, count));
    }
}

}  // namespace ddmr::tools
