// summary.json's and result.json's "fast_forward" section
// (tools/fast_forward_report.cpp), and the front ends' switches: `run
// --no-fast-forward`, `scenario --no-fast-forward`, `fast-forward: false`.
#include "fast_forward_report.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>

#include "support/process.hpp"
#include "support/scenario_cli.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::tools {
namespace {

using nlohmann::json;
using test::run_command;
using test::sh_quote;

json run_summary(const test::TempDir& dir, const std::string& name, const std::string& args) {
    const auto out = dir / name;
    const auto r = run_command(sh_quote(test::cli_path().string()) + " run -q --out " + sh_quote(out.string()) + " " +
                               args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return json::parse(test::read_text(out / "summary.json"));
}

TEST(FastForwardReport, NamesTheLoopsItSkippedAndWhyOthersWereNot) {
    const test::TempDir dir;
    const std::string elf = (test::test_firmware_dir() / "ff_sram_counter.elf").string();
    const json ff = run_summary(dir, "on", "--firmware " + sh_quote(elf) + " --seconds 0.2")["fast_forward"];
    ASSERT_TRUE(ff["enabled"].get<bool>());
    EXPECT_GT(ff["cycles_skipped"].get<uint64_t>(), 0U);
    EXPECT_GT(ff["skipped_share"].get<double>(), 0.0);
    EXPECT_LT(ff["skipped_share"].get<double>(), 1.0);
    ASSERT_FALSE(ff["loops"].empty());
    bool wait_skipped = false;
    uint64_t skips = 0, mismatches = 0, taken_back = 0;
    for (const json& l : ff["loops"]) {
        EXPECT_EQ(l["cycles_skipped"].get<uint64_t>() % l["pass_cycles"].get<uint64_t>(), 0U);  // whole passes
        wait_skipped |= l["skips"].get<uint64_t>() > 0;
        skips += l["skips"].get<uint64_t>();
        mismatches += l["mismatches"].get<uint64_t>();
        taken_back += l["taken_back"].get<uint64_t>();
    }
    EXPECT_TRUE(wait_skipped);
    EXPECT_EQ(skips, ff["skips"].get<uint64_t>());  // the loops' counts add up to the run's
    EXPECT_EQ(mismatches, ff["mismatches"].get<uint64_t>());
    EXPECT_EQ(taken_back, ff["taken_back"].get<uint64_t>());
    bool counter_named = false;
    for (const json& r : ff["not_skipped"]) {
        counter_named |= r["reason"].get<std::string>().find("from pass to pass") != std::string::npos &&
                         r["function"].get<std::string>() == "main";
    }
    EXPECT_TRUE(counter_named) << ff["not_skipped"].dump();
}

TEST(FastForwardReport, NoFastForwardSaysSoAndChangesNothingElse) {
    const test::TempDir dir;
    const std::string elf = (test::test_firmware_dir() / "ff_isr_flag.elf").string();
    const std::string args = "--firmware " + sh_quote(elf) + " --seconds 0.15";
    json on = run_summary(dir, "on", args);
    json off = run_summary(dir, "off", args + " --no-fast-forward");
    EXPECT_EQ(off["fast_forward"], (json{{"enabled", false}}));
    EXPECT_EQ(test::read_text(dir / "on" / "uart.txt"), test::read_text(dir / "off" / "uart.txt"));
    EXPECT_NE(test::read_text(dir / "on" / "uart.txt").find("tick"), std::string::npos);
    for (json* j : {&on, &off}) {
        for (const char* k : {"fast_forward", "wall_seconds", "mcycles_per_s"}) j->erase(k);
    }
    EXPECT_EQ(on, off);
}

TEST(FastForwardReport, AUartPollFromTheHostIsExactInAScenario) {
    // ff_fixture.c, FF_UDR_POLL: `while (!(UCSR0A & _BV(RXC0))) {}`, bytes written by the scenario.
    const test::TempDir dir;
    const auto file = test::write_text(dir, "udr.yaml", R"(name: udr
timeout: 1s
steps:
  - delay: 50ms
  - write-serial: "ab"
  - delay: 30ms
  - write-serial: "c"
  - wait-serial: {text: done, timeout: 0.5s}
)");
    const std::string elf = sh_quote((test::test_firmware_dir() / "ff_udr_poll.elf").string());
    const auto on = test::scenario(sh_quote(file.string()) + " --firmware " + elf + " --out " + sh_quote((dir / "on").string()));
    ASSERT_EQ(on.exit_code, 0) << on.out << on.err;
    const auto off = test::scenario(sh_quote(file.string()) + " --firmware " + elf + " --no-fast-forward --out " +
                                    sh_quote((dir / "off").string()));
    ASSERT_EQ(off.exit_code, 0) << off.out << off.err;
    const std::string text = test::read_text(dir / "on" / "udr" / "uart.txt");
    EXPECT_NE(text.find("byte 97 at"), std::string::npos) << text;  // 'a'
    EXPECT_EQ(text, test::read_text(dir / "off" / "udr" / "uart.txt"));
    json a = test::result_of(dir / "on" / "udr");
    json b = test::result_of(dir / "off" / "udr");
    EXPECT_TRUE(a["fast_forward"]["enabled"].get<bool>());
    EXPECT_FALSE(b["fast_forward"]["enabled"].get<bool>());
    a.erase("fast_forward");
    b.erase("fast_forward");
    EXPECT_EQ(a, b);
}

TEST(FastForwardReport, AScenarioCanTurnItOff) {
    const test::TempDir dir;
    const auto file = test::write_text(dir, "off.yaml", "name: off\nfast-forward: false\ntimeout: 0.1s\nsteps:\n"
                                                        "  - delay: 50ms\n");
    const std::string elf = sh_quote((test::test_firmware_dir() / "ff_isr_flag.elf").string());
    const auto r = test::scenario(sh_quote(file.string()) + " --firmware " + elf + " --out " + sh_quote((dir / "o").string()));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_FALSE(test::result_of(dir / "o" / "off")["fast_forward"]["enabled"].get<bool>());
    const auto bad = test::write_text(dir, "bad.yaml", "name: bad\nfast-forward: maybe\ntimeout: 0.1s\nsteps:\n"
                                                       "  - delay: 50ms\n");
    const auto e = test::scenario(sh_quote(bad.string()) + " --firmware " + elf + " --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(e.exit_code, 2);
    EXPECT_NE(e.err.find("fast-forward"), std::string::npos) << e.err;
}

}  // namespace
}  // namespace ddmr::tools
