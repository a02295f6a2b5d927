// `ddmr-hil report` and tools/report/make_report.py: plots and report.md for
// a run, deterministic, with Debian's python3 whatever PATH says (issue 19).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

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
    const auto c = run_command(cli + " compare " + sh_quote(out.string()));
    ASSERT_LE(c.exit_code, 1);
    EXPECT_NE(c.out.find("ddmr-hil report " + out.string()), std::string::npos) << c.out;  // where the plots come from
    // A python3 without matplotlib first on PATH: the command still uses Debian's.
    const auto bin = dir / "bin";
    std::filesystem::create_directories(bin);
    std::ofstream(bin / "python3") << "#!/bin/sh\necho 'No module named matplotlib' >&2\nexit 1\n";
    std::filesystem::permissions(bin / "python3", std::filesystem::perms::owner_all);
    const auto r = run_command("PATH=" + sh_quote(bin.string()) + ":$PATH " + cli + " report " + sh_quote(out.string()));
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
    // Every plot has its caption; the currents' says how they are averaged.
    EXPECT_NE(md.find("![Motor currents](currents.png)\n\n*The motor currents, averaged over 25 PWM periods (51.0 ms)"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("the gap between the lines is the odometry's drift"), std::string::npos) << md;
    // Same run, same bytes.
    const std::string svg = read_text(out / "xy.svg");
    ASSERT_EQ(run_command("/usr/bin/python3 " + script() + " " + sh_quote(out.string())).exit_code, 0);
    EXPECT_EQ(read_text(out / "xy.svg"), svg);
}

TEST(MakeReport, TheCommandRefusesAnotherCommandsFolderInOneLine) {
    TempDir dir;
    const std::string cli = sh_quote(cli_path().string());
    ASSERT_EQ(run_command(cli + " sim --duration 0.5 --out " + sh_quote((dir / "sim").string())).exit_code, 0);
    const auto r = run_command(cli + " report " + sh_quote((dir / "sim").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("sim: a `ddmr-hil sim` output folder; report takes the output folder of `ddmr-hil run` or "
                         "`profile`"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

TEST(MakeReport, MissingRunIsAnErrorNamingIt) {
    TempDir dir;
    const auto r = run_command("/usr/bin/python3 " + script() + " " + sh_quote((dir / "none").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("none"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ddmr::test
