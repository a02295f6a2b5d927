// tools/report/make_report.py: plots and report.md for a run, deterministic.
#include <gtest/gtest.h>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

std::string script() { return sh_quote((source_dir() / "tools/report/make_report.py").string()); }

TEST(MakeReport, WritesEveryPlotAndTheKeyNumbers) {
    TempDir dir;
    const auto out = dir / "run";
    const std::string cli = sh_quote(cli_path().string());
    ASSERT_EQ(run_command(cli + " run --case 2 -q --out " + sh_quote(out.string())).exit_code, 0);
    ASSERT_LE(run_command(cli + " compare " + sh_quote(out.string())).exit_code, 1);
    const auto r = run_command("/usr/bin/python3 " + script() + " " + sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    for (const char* p : {"xy", "tracking_error", "wheel_speeds", "drive", "currents", "battery"}) {
        EXPECT_TRUE(std::filesystem::exists(out / (std::string(p) + ".png"))) << p;
        EXPECT_TRUE(std::filesystem::exists(out / (std::string(p) + ".svg"))) << p;
    }
    const std::string md = read_text(out / "report.md");
    EXPECT_NE(md.find("# ddmr-hil run: case 2"), std::string::npos);
    EXPECT_NE(md.find("| loop iterations, mean period | 800,"), std::string::npos) << md;
    EXPECT_NE(md.find("log_vs_sim"), std::string::npos);
    EXPECT_NE(md.find("![X-Y trajectories](xy.png)"), std::string::npos);
    // Same run, same bytes.
    const std::string svg = read_text(out / "xy.svg");
    ASSERT_EQ(run_command("/usr/bin/python3 " + script() + " " + sh_quote(out.string())).exit_code, 0);
    EXPECT_EQ(read_text(out / "xy.svg"), svg);
}

TEST(MakeReport, MissingRunIsAnErrorNamingIt) {
    TempDir dir;
    const auto r = run_command("/usr/bin/python3 " + script() + " " + sh_quote((dir / "none").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("none"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ddmr::test
