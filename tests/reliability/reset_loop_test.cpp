// A sketch whose `new` links to `call 0` (issue 32; tests/firmware/
// new_without_core): the call is reported when the ELF is built or loaded,
// the first restart is told with its PC, and the run ends with reset_loop
// (exit 3) instead of a silent time_limit.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fmt/format.h>

#include <string>

#include "hil/zero_calls.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path sketch() { return source_dir() / "tests/firmware/new_without_core/new_without_core.ino"; }
fs::path elf() { return test_firmware_dir() / "new_without_core.elf"; }

/// watch()'s `call 0`, where the scan finds it.
uint32_t call_pc() { return hil::find_zero_calls(hil::ElfImage::read(elf())).calls.at(0).pc; }

/// What both runs say about the restarts, and their summary.json.
void expect_reset_loop(const ProcessResult& r, const fs::path& out) {
    EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
    const std::string from = fmt::format("`call 0` at PC 0x{:04x} in watch(unsigned char)", call_pc());
    EXPECT_NE(r.err.find("ddmr-hil: warning: the firmware restarted from address 0 without a reset at cycle "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find(from + "; restarts like it are counted"), std::string::npos) << r.err;
    const json s = json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(s["exit_reason"], "reset_loop");
    EXPECT_EQ(s["exit_message"].get<std::string>().rfind("reset loop: the firmware restarted from address 0 without a "
                                                         "reset more than 10 times within a simulated second",
                                                         0),
              0U)
        << s["exit_message"];
    EXPECT_NE(r.err.find(s["exit_message"].get<std::string>()), std::string::npos) << r.err;
    EXPECT_GE(s["unasked_resets"]["count"].get<int>(), 11);
    EXPECT_EQ(s["unasked_resets"]["first"]["from"], from);
    ASSERT_EQ(s["calls_to_address_0"]["calls"].size(), 1U);
    EXPECT_EQ(s["calls_to_address_0"]["calls"][0]["function"], "watch(unsigned char)");
    EXPECT_EQ(s["calls_to_address_0"]["calls"][0]["pc"], call_pc());
    EXPECT_LT(s["sim_seconds"].get<double>(), 0.01);  // 11 restarts of about 0.1 ms each, not the 5 s asked
}

TEST(ResetLoop, RunningTheElfWarnsOfTheCallAndEndsWithResetLoop) {
    TempDir dir;
    const auto r = run_command(sh_quote(cli_path().string()) + " run -q --seconds 5 --firmware " +
                               sh_quote(elf().string()) + " --out " + sh_quote((dir / "out").string()));
    expect_reset_loop(r, dir / "out");
    const std::string scan =
        fmt::format("ddmr-hil: warning: firmware {}: `call 0` at 0x{:04x} in watch(unsigned char): an unguarded call "
                    "to address 0 restarts the firmware (the likely callee is one of the ELF's unresolved weak "
                    "symbols, which nothing defines: operator new(unsigned int), serialEvent())\n",
                    elf().string(), call_pc());
    EXPECT_NE(r.err.find(scan), std::string::npos) << r.err;
}

TEST(ResetLoop, BuildingTheSketchReportsTheCallOnce) {
    // A real arduino-builder run, into a cache of the test's own.
    TempDir dir;
    const auto run_sketch = [&](const std::string& out) {
        return run_command("XDG_CACHE_HOME=" + sh_quote((dir / "cache").string()) + " " +
                           sh_quote(cli_path().string()) + " run -q --seconds 5 --sketch " +
                           sh_quote(sketch().string()) + " --out " + sh_quote((dir / out).string()));
    };
    const auto r = run_sketch("out");
    expect_reset_loop(r, dir / "out");
    // Said by the build (its warnings), and not again by the run of what it built.
    const std::string said = fmt::format("sketch {}: warning: `call 0` at 0x{:04x} in watch(unsigned char): an "
                                         "unguarded call to address 0 restarts the firmware",
                                         sketch().string(), call_pc());
    EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning: firmware "), std::string::npos) << r.err;
    const json s = json::parse(read_text(dir / "out/summary.json"));
    const auto& warnings = s["firmware_source"]["warnings"];
    ASSERT_EQ(warnings.size(), 1U) << warnings;
    EXPECT_NE(warnings[0].get<std::string>().find("operator new(unsigned int)"), std::string::npos) << warnings;
    // From the cache: said again (the scan is not kept in the cache entry).
    const auto again = run_sketch("again");
    EXPECT_NE(again.err.find(said), std::string::npos) << again.err;
    EXPECT_EQ(json::parse(read_text(dir / "again/summary.json"))["firmware_source"]["from_cache"], true);
}

}  // namespace
}  // namespace ddmr::test
