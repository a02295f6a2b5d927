#pragma once
// `ddmr-hil merge SHARD_DIR... --out DIR`: combines the --out folders of a
// sharded `ddmr-hil scenario --shard I/N` run into the folder an unsharded
// run writes (byte-identical results.json and scenario folders).
#include "subcommand.hpp"

namespace ddmr::tools {

Subcommand register_merge_command(CLI::App& app);

}  // namespace ddmr::tools
