// Both time limits exist and end a run cleanly (issue 9): the simulated-time
// limit (--seconds, a scenario's timeout) and the wall-clock limit
// (--wall-timeout); each gives exit 3 with the artifacts written, and
// neither can be switched off by a zero or negative value.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

std::string cli() { return sh_quote(cli_path().string()); }

TEST(Timeouts, WallClockLimitStopsARunAndKeepsItsArtifacts) {
    TempDir dir;
    // Executing every pass, case 1 takes about 1.5 s of wall time (about
    // 0.5 s with fast-forward: too close to a 0.5 s limit).
    const auto r = run_command(cli() + " run -q --no-fast-forward --wall-timeout 0.5 --out " +
                               sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("wall-clock timeout after 0.5 s"), std::string::npos) << r.err;
    const auto s = nlohmann::json::parse(read_text(dir / "out/summary.json"));
    EXPECT_EQ(s["exit_reason"], "wall_timeout");
    EXPECT_LT(s["sim_seconds"].get<double>(), 19.0);  // stopped before the end of case 1
    for (const char* f : {"uart.txt", "truth.csv", "firmware.csv", "eeprom.bin", "isr.json"}) {
        EXPECT_TRUE(fs::exists(dir / "out" / f)) << f;
    }
}

TEST(Timeouts, SimulatedTimeLimitStopsARun) {
    TempDir dir;
    const auto r = run_command(cli() + " run -q --seconds 6 --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_NE(r.err.find("timeout after 6 simulated s"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(dir / "out/uart.txt"));
}

TEST(Timeouts, WallClockLimitStopsAScenarioWorker) {
    TempDir dir;
    const fs::path f = dir / "long.yaml";
    std::ofstream(f) << "name: long\ntimeout: 600s\nsteps:\n  - delay: 590s\n";
    // Executing every pass: 590 simulated s take far longer than 1 s of wall time.
    const auto r = run_command(cli() + " scenario " + sh_quote(f.string()) +
                               " --no-fast-forward --wall-timeout 1 --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
    EXPECT_NE(r.out.find("wall-clock timeout after 1 s"), std::string::npos) << r.out;
    const auto results = nlohmann::json::parse(read_text(dir / "out/results.json"));
    EXPECT_EQ(results["scenarios"][0]["verdict"], "firmware");
}

TEST(Timeouts, NeitherLimitCanBeSwitchedOff) {
    TempDir dir;
    for (const char* args : {"run --wall-timeout 0", "run --wall-timeout -1", "run --seconds 0", "run --seconds -5"}) {
        const auto r = run_command(cli() + " " + args + " --out " + sh_quote((dir / "out").string()));
        EXPECT_EQ(r.exit_code, 2) << args;
        EXPECT_FALSE(fs::exists(dir / "out")) << args;
    }
    const fs::path f = dir / "s.yaml";
    std::ofstream(f) << "timeout: 1s\nsteps:\n  - delay: 1ms\n";
    const auto r = run_command(cli() + " scenario " + sh_quote(f.string()) + " --wall-timeout 0 --out " +
                               sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 2);
}

}  // namespace
}  // namespace ddmr::test
