// `run --verify-fast-forward`: a run equal both ways says so at every
// checkpoint; a difference is narrowed to the first stop at which it shows,
// with the PC and the bytes (the difference here is made on purpose: the
// second run gets a byte on its serial line that the first does not).
#include "fast_forward_verify.hpp"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::tools {
namespace {

using nlohmann::json;

FirmwareRunOptions fixture_run(const std::string& fixture, const std::filesystem::path& out, double seconds) {
    FirmwareRunOptions o;
    o.firmware = test::test_firmware_dir() / (fixture + ".elf");
    o.out_dir = out;
    o.max_sim_seconds = seconds;
    return o;
}

TEST(FastForwardVerify, ARunEqualBothWaysIsEqualAtEveryCheckpoint) {
    const test::TempDir dir;
    // Polls an encoder pin the plant drives: jumps end at its edges.
    const VerifiedRun v = run_verifying_fast_forward(fixture_run("ff_pin_poll", dir / "run", 0.2));
    EXPECT_EQ(v.result.exit, RunExit::kTimeLimit) << v.result.message;
    EXPECT_FALSE(v.verification.difference.has_value()) << verification_line(v.verification, 16'000'000);
    EXPECT_EQ(v.verification.checkpoints_equal, 20U);  // every 10 ms before the end at 0.2 s, and the end
    EXPECT_EQ(v.verification.checked_to_cycle, v.result.cycles_total);
    const json j = json::parse(test::read_text(dir / "run" / "fast_forward_verify.json"));
    EXPECT_TRUE(j["equal"].get<bool>());
    EXPECT_TRUE(j["first_difference"].is_null());
    EXPECT_TRUE(std::filesystem::exists(dir / "run" / "summary.json"));  // the run's artifacts, as `run` writes them
}

TEST(FastForwardVerify, NamesTheFirstStopAtWhichTwoRunsDiffer) {
    const test::TempDir dir;
    const FirmwareRunOptions a = fixture_run("echo_fixture", dir / "run", 0.1);
    FirmwareRunOptions b = a;
    b.fast_forward = false;
    b.sends.push_back(FirmwareRunOptions::Send{"x", 0.0405});  // 648,000 cycles
    const VerifiedRun v = run_in_lockstep_with(a, b);
    ASSERT_TRUE(v.verification.difference.has_value());
    const FastForwardDifference& d = *v.verification.difference;
    EXPECT_TRUE(d.narrowed);
    EXPECT_EQ(v.verification.checkpoints_equal, 4U);  // 10, 20, 30, 40 ms
    // The byte is in after one frame: 10 bits of 8 x (UBRR0 + 1) = 1664
    // cycles each (U2X0, UBRR0 = 207: 9615 baud), sent from the first
    // instruction boundary at or after 648,000. The first stop that differs
    // comes then, within an instruction of the last equal one.
    EXPECT_GE(d.with_ff.cycle, 648'000U + 16'640U);
    EXPECT_LE(d.with_ff.cycle, 648'000U + 16'640U + 8U);
    EXPECT_GT(d.with_ff.cycle, d.last_equal_cycle);
    EXPECT_LE(d.with_ff.cycle - d.last_equal_cycle, 8U);
    EXPECT_EQ(d.with_ff.cycle, d.without_ff.cycle);
    ASSERT_FALSE(d.comparison.shown.empty());
    bool names_ucsr0a = false;
    for (const hil::StateDifference& s : d.comparison.shown) names_ucsr0a |= s.what == "UCSR0A";
    EXPECT_TRUE(names_ucsr0a) << verification_line(v.verification, 16'000'000);
    const json j = json::parse(test::read_text(dir / "run" / "fast_forward_verify.json"));
    EXPECT_FALSE(j["equal"].get<bool>());
    EXPECT_EQ(j["first_difference"]["cycle"].get<uint64_t>(), d.with_ff.cycle);
    EXPECT_EQ(j["first_difference"]["differences_total"].get<std::size_t>(), d.comparison.total);
}

TEST(FastForwardVerify, TheCommandExitsOneOnADifferenceAndRefusesNoFastForward) {
    const test::TempDir dir;
    const std::string cli = test::sh_quote(test::cli_path().string());
    const std::string elf = test::sh_quote((test::test_firmware_dir() / "ff_isr_flag.elf").string());
    // Its own private folder for the second run: empty again at the end.
    std::filesystem::create_directories(dir / "tmp");
    const auto ok = test::run_command("TMPDIR=" + test::sh_quote((dir / "tmp").string()) + " " + cli +
                                      " run -q --firmware " + elf + " --seconds 0.05 --verify-fast-forward --out " +
                                      test::sh_quote((dir / "ok").string()));
    EXPECT_EQ(ok.exit_code, 0) << ok.err;
    const json j = json::parse(test::read_text(dir / "ok" / "fast_forward_verify.json"));
    EXPECT_GE(j["checkpoints_equal"].get<int>(), 5);  // every 10 ms, and the end
    EXPECT_NE(ok.out.find(fmt::format("fast-forward verified: the runs with and without it were equal at {} checkpoints",
                                      j["checkpoints_equal"].get<int>())),
              std::string::npos)
        << ok.out;
    EXPECT_TRUE(std::filesystem::is_empty(dir / "tmp"));
    const auto bad = test::run_command(cli + " run -q --firmware " + elf +
                                       " --seconds 0.05 --verify-fast-forward --no-fast-forward --out " +
                                       test::sh_quote((dir / "bad").string()));
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("--no-fast-forward excludes --verify-fast-forward"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
}

}  // namespace
}  // namespace ddmr::tools
