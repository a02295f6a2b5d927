#include "merge_command.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <memory>
#include <optional>

#include "common/atomic_file.hpp"
#include "scenario/suite_results.hpp"
#include "shard_set.hpp"
#include "sweep_merge.hpp"

namespace ddmr::tools {
namespace {
namespace fs = std::filesystem;
namespace sc = scenario;
using nlohmann::json;

struct MergeCli {
    std::vector<std::string> shard_dirs;
    std::string out_dir;
    std::string junit;
};

json read_json(const fs::path& p) {
    std::ifstream in(p);
    if (!in) throw std::runtime_error(p.string() + ": missing (is this the --out folder of `scenario --shard`?)");
    try {
        return json::parse(in);
    } catch (const json::exception& e) {
        throw std::runtime_error(p.string() + ": malformed JSON: " + e.what());
    }
}

int run_merge(const MergeCli& cli) {
    if (are_sweep_shards(cli.shard_dirs)) {
        if (!cli.junit.empty()) throw std::invalid_argument("--junit: a sweep has no JUnit report");
        return merge_sweep_shards(cli.shard_dirs, cli.out_dir);
    }
    // Check that the shards are one suite, each shard once, before writing.
    std::optional<std::vector<std::string>> suite;
    std::vector<ShardFolder> folders;
    std::map<std::string, fs::path> folder_of;  // scenario name -> its shard's folder
    for (const auto& d : cli.shard_dirs) {
        const json shard = read_json(fs::path(d) / "shard.json");
        const sc::Shard s = sc::parse_shard(shard.at("shard").get<std::string>());
        const auto names = shard.at("suite").get<std::vector<std::string>>();
        if (!suite) suite = names;
        if (names != *suite) throw std::invalid_argument(fmt::format("{}: a shard of another suite (its scenarios differ)", d));
        folders.push_back({d, s});
        for (std::size_t k = 0; k < names.size(); ++k) {
            if (s.contains(k)) folder_of[names[k]] = fs::path(d) / names[k];
        }
    }
    check_shard_set(folders);
    std::vector<sc::ScenarioResult> all;
    all.reserve(suite->size());
    for (const auto& name : *suite) all.push_back(sc::read_scenario_result(folder_of.at(name)));
    const fs::path out = cli.out_dir;
    prepare_output_dir(out);
    for (const auto& name : *suite) {
        fs::remove_all(out / name);
        fs::copy(folder_of.at(name), out / name, fs::copy_options::recursive);
    }
    return sc::finish_suite(all, out, cli.junit);
}

}  // namespace

Subcommand register_merge_command(CLI::App& app) {
    auto cli = std::make_shared<MergeCli>();
    CLI::App* sub = app.add_subcommand(
        "merge",
        "Combine the --out folders of `ddmr-hil scenario --shard I/N` runs (every shard once) into one folder, "
        "identical to an unsharded run's; same exit codes as `scenario`. Folders of `ddmr-hil sweep --shard I/N` "
        "are merged into the unsharded sweep's CSVs and sweep.json (no plots; same exit codes as `sweep`).");
    sub->add_option("shards", cli->shard_dirs, "The shards' --out folders")->required()->check(CLI::ExistingDirectory);
    sub->add_option("--out", cli->out_dir, "The merged folder")->required();
    sub->add_option("--junit", cli->junit, "Also write JUnit XML here (times are not known after a merge: 0)");
    return {sub, [cli] { return run_merge(*cli); }};
}

}  // namespace ddmr::tools
