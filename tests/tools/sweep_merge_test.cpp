// Tests for tools/sweep_merge and `sweep --shard`: a small sweep run whole
// and as three shards in parallel processes (xargs -P, as GNU parallel or a
// CI matrix would), merged, gives the same files byte for byte.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

class SweepMerge : public ::testing::Test {
protected:
    std::string cli() const { return sh_quote(cli_path().string()); }
    std::string out(const std::string& name) const { return " --out " + sh_quote((dir_ / name).string()); }
    /// Two studies, six runs (fig5_2: four gains on the 20 s line; fig5_8: two
    /// circles), on the kinematic robot: fast, and the runs differ in length.
    static constexpr const char* kSweep = " sweep --study fig5_8,fig5_2 --plant kinematic --no-plot -q -j 1";
    TempDir dir_;
};

TEST_F(SweepMerge, MergedShardsEqualTheUnshardedSweep) {
    const auto whole = run_command(cli() + kSweep + out("whole"));
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    // Three shards, two at a time, each its own process.
    const fs::path script = dir_ / "shard.sh";
    std::ofstream(script) << "i=$(echo \"$1\" | cut -d/ -f1)\nexec " << cli() << kSweep << " --shard \"$1\" --out "
                          << sh_quote((dir_ / "shard").string()) << "-\"$i\"\n";
    const fs::path list = dir_ / "shards.txt";
    std::ofstream(list) << "1/3\n2/3\n3/3\n";
    const auto sharded =
        run_command("xargs -r -a " + sh_quote(list.string()) + " -P 2 -n 1 sh " + sh_quote(script.string()));
    ASSERT_EQ(sharded.exit_code, 0) << sharded.err;
    // Round robin over the runs in study order: shard 1 of 3 holds runs 1 and 4.
    EXPECT_TRUE(fs::exists(dir_ / "shard-1/run-0001.csv"));
    EXPECT_TRUE(fs::exists(dir_ / "shard-1/run-0004.json"));
    EXPECT_FALSE(fs::exists(dir_ / "shard-1/run-0002.csv"));
    EXPECT_FALSE(fs::exists(dir_ / "shard-1/sweep.json"));
    const auto merged = run_command(cli() + " merge " + sh_quote((dir_ / "shard-2").string()) + " " +
                                    sh_quote((dir_ / "shard-1").string()) + " " +
                                    sh_quote((dir_ / "shard-3").string()) + out("merged"));
    ASSERT_EQ(merged.exit_code, 0) << merged.err;
    EXPECT_NE(merged.out.find("2 studies, 6 runs"), std::string::npos) << merged.out;
    const auto want = file_tree(dir_ / "whole");
    ASSERT_EQ(want.size(), 3U);  // fig5_8.csv, fig5_2.csv, sweep.json
    EXPECT_EQ(file_tree(dir_ / "merged"), want);
}

TEST_F(SweepMerge, ShardsOfAnotherSweepMissingOrTwiceAreRefused) {
    for (const char* s : {"1/2", "2/2"}) {
        const auto r = run_command(cli() + kSweep + " --shard " + s + out(std::string("s") + s[0]));
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    const auto other = run_command(cli() + " sweep --study fig5_8 --plant kinematic --no-plot -q --shard 2/2" +
                                   out("other"));
    ASSERT_EQ(other.exit_code, 0) << other.err;
    const std::string s1 = " " + sh_quote((dir_ / "s1").string());
    const std::string s2 = " " + sh_quote((dir_ / "s2").string());
    const std::vector<std::pair<std::string, std::string>> refused = {
        {s1, "shard 2/2 is missing"},
        {s1 + s1, "given twice"},
        {s1 + " " + sh_quote((dir_ / "other").string()), "another sweep"},
        {s1 + s2 + " --junit " + sh_quote((dir_ / "j.xml").string()), "--junit"},
    };
    for (const auto& [args, named] : refused) {
        const auto r = run_command(cli() + " merge" + args + out("m"));
        EXPECT_EQ(r.exit_code, 2) << args;
        EXPECT_NE(r.err.find(named), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "m")) << args;
    }
    for (const char* bad : {"0/2", "3/2", "1/0", "a/b", "1"}) {
        const auto r = run_command(cli() + kSweep + " --shard " + bad + out("bad"));
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.err.find("--shard"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "bad"));
    }
}

}  // namespace
}  // namespace ddmr::test
