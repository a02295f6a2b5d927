// Tests for tools/merge_command and `scenario --shard`: shards run in
// parallel processes (xargs -P, as GNU parallel or a CI matrix would) and
// merged give the same folder, byte for byte, as one unsharded run.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

class MergeCommand : public ::testing::Test {
protected:
    void SetUp() override {
        // Short scenarios: the firmware's answer to three case bytes.
        const char* cases[][2] = {{"one", "1"}, {"two", "2"}, {"other", "7"}, {"again", "1"}, {"late", "2"}};
        for (const auto& c : cases) {
            const fs::path p = dir_ / (std::string(c[0]) + ".yaml");
            std::ofstream(p) << "name: " << c[0] << "\ntimeout: 7s\nsteps:\n  - write-serial: \"" << c[1]
                             << "\"\n  - delay: 5100ms\n  - expect-serial: \"0\\\\.[46]m\"\n";
            files_ += " " + sh_quote(p.string());
        }
    }
    std::string cli() const { return sh_quote(cli_path().string()); }
    TempDir dir_;
    std::string files_;
};

TEST_F(MergeCommand, MergedShardsEqualTheUnshardedRun) {
    const auto whole = run_command(cli() + " scenario" + files_ + " -j 2 --out " + sh_quote((dir_ / "whole").string()));
    EXPECT_EQ(whole.exit_code, 1) << whole.err;  // 'other' gets "X": its expect-serial fails
    // Three shards, two at a time, each its own process.
    const fs::path script = dir_ / "shard.sh";
    std::ofstream(script) << "i=$(echo \"$1\" | cut -d/ -f1)\nexec " << cli() << " scenario" << files_
                          << " -j 1 --shard \"$1\" --out " << sh_quote((dir_ / "shard").string()) << "-\"$i\"\n";
    const fs::path list = dir_ / "shards.txt";
    std::ofstream(list) << "1/3\n2/3\n3/3\n";
    const std::string shards = "xargs -r -a " + sh_quote(list.string()) + " -P 2 -n 1 sh " + sh_quote(script.string());
    const auto sharded = run_command(shards);
    EXPECT_NE(sharded.exit_code, 0) << sharded.err;  // one shard holds the failing scenario
    ASSERT_TRUE(fs::exists(dir_ / "shard-1")) << sharded.err;
    const auto merged = run_command(cli() + " merge " + sh_quote((dir_ / "shard-1").string()) + " " +
                                    sh_quote((dir_ / "shard-3").string()) + " " + sh_quote((dir_ / "shard-2").string()) +
                                    " --out " + sh_quote((dir_ / "merged").string()));
    EXPECT_EQ(merged.exit_code, 1) << merged.err;
    EXPECT_EQ(file_tree(dir_ / "merged"), file_tree(dir_ / "whole"));
    // Round robin: shard 1 of 3 holds the 1st and 4th scenarios.
    EXPECT_TRUE(fs::exists(dir_ / "shard-1/one"));
    EXPECT_TRUE(fs::exists(dir_ / "shard-1/again"));
    EXPECT_FALSE(fs::exists(dir_ / "shard-1/two"));
}

TEST_F(MergeCommand, IncompleteOrMixedShardsAreRefused) {
    for (const char* s : {"1/2", "2/2"}) {
        const auto r = run_command(cli() + " scenario" + files_ + " --shard " + s + " --out " +
                                   sh_quote((dir_ / (std::string("s") + s[0])).string()));
        ASSERT_NE(r.exit_code, 2) << r.err;
    }
    const auto missing = run_command(cli() + " merge " + sh_quote((dir_ / "s1").string()) + " --out " +
                                     sh_quote((dir_ / "m").string()));
    EXPECT_EQ(missing.exit_code, 2);
    EXPECT_NE(missing.err.find("shard 2/2 is missing"), std::string::npos) << missing.err;
    EXPECT_FALSE(fs::exists(dir_ / "m"));
    const auto twice = run_command(cli() + " merge " + sh_quote((dir_ / "s1").string()) + " " +
                                   sh_quote((dir_ / "s1").string()) + " --out " + sh_quote((dir_ / "m").string()));
    EXPECT_EQ(twice.exit_code, 2);
    EXPECT_NE(twice.err.find("given twice"), std::string::npos) << twice.err;
    for (const char* bad : {"0/2", "3/2", "1/0", "a/b", "1"}) {
        const auto r = run_command(cli() + " scenario" + files_ + " --shard " + bad + " --out " +
                                   sh_quote((dir_ / "bad").string()));
        EXPECT_EQ(r.exit_code, 2) << bad;
        EXPECT_NE(r.err.find("--shard"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(dir_ / "bad"));
    }
}

}  // namespace
}  // namespace ddmr::test
