// `ddmr-hil report` and tools/report/make_report.py: plots and report.md for
// a run, a sim folder, a scenario suite (a report per scenario and an index)
// and one scenario's folder, deterministic, with Debian's python3 whatever
// PATH says (issue 19).
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

/// Runs `ddmr-hil report DIR` twice: the second must write the same bytes.
ProcessResult report_twice(const std::filesystem::path& dir) {
    const std::string cmd = sh_quote(cli_path().string()) + " report " + sh_quote(dir.string());
    const ProcessResult first = run_command(cmd);
    if (first.exit_code != 0) return first;
    const auto files = file_tree(dir);
    const ProcessResult second = run_command(cmd);
    EXPECT_EQ(file_tree(dir), files) << "the same folder gave other bytes";
    return second;
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(MakeReport, PlotsASimFolderWithWhatItsPlantHas) {
    TempDir dir;
    const std::string cli = sh_quote(cli_path().string());
    const auto sim = dir / "sim";
    ASSERT_EQ(run_command(cli + " sim --model firmware --duration 1 --out " + sh_quote(sim.string())).exit_code, 0);
    const auto r = report_twice(sim);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, (sim / "report.md").string() + "\n");
    for (const char* p : {"xy", "tracking_error", "lyapunov", "wheel_speeds", "drive", "currents", "battery"}) {
        EXPECT_TRUE(std::filesystem::exists(sim / (std::string(p) + ".png"))) << p;
        EXPECT_TRUE(std::filesystem::exists(sim / (std::string(p) + ".svg"))) << p;
    }
    const std::string md = read_text(sim / "report.md");
    EXPECT_TRUE(has(md, "# ddmr-hil sim: case1, firmware model\n")) << md;
    EXPECT_TRUE(has(md, "| case | case1: circle R = 0.6 m, T = 12 s |")) << md;
    EXPECT_TRUE(has(md, "| duration, control period, plant step | 1 s,")) << md;
    EXPECT_TRUE(has(md, "| EEPROM log | written, ")) << md;
    EXPECT_FALSE(has(md, "wall")) << "the wall time is not the same twice";
    EXPECT_TRUE(has(md, "![X-Y trajectories](xy.png)\n\n*The goal's path (dashed)")) << md;
    EXPECT_TRUE(has(md, "![Motor currents](currents.png)\n\n*The motor currents, averaged over 25 PWM periods")) << md;
    EXPECT_FALSE(has(md, "## Not available")) << md;

    // The kinematic plant has no motors: no currents, a fixed battery; report.md says so.
    const auto kin = dir / "kinematic";
    ASSERT_EQ(run_command(cli + " sim --plant kinematic --duration 0.5 --out " + sh_quote(kin.string())).exit_code, 0);
    const auto k = run_command(cli + " report " + sh_quote(kin.string()));
    ASSERT_EQ(k.exit_code, 0) << k.err;
    EXPECT_TRUE(std::filesystem::exists(kin / "xy.png"));
    EXPECT_FALSE(std::filesystem::exists(kin / "currents.png"));
    const std::string kmd = read_text(kin / "report.md");
    EXPECT_TRUE(has(kmd, "## Not available\n\n")) << kmd;
    EXPECT_TRUE(has(kmd, "- Motor currents: ia1_A, ia2_A in sim.csv never change (the kinematic plant has no motors")) << kmd;
    EXPECT_TRUE(has(kmd, "- Battery voltage: vbatt_V in sim.csv never changes")) << kmd;
    EXPECT_FALSE(has(kmd, "- Wheel speeds")) << kmd;
}

TEST(MakeReport, PlotsAScenarioSuiteEachScenarioAndAnIndex) {
    TempDir dir;
    const std::string cli = sh_quote(cli_path().string());
    // Two short scenarios on the reference firmware: case 1's first second (it
    // starts 5 s after the case byte); the robot has left the origin by less
    // than 1 m (passes), and is not at (5, 0) (fails).
    const std::string steps =
        "timeout: 8s\nsteps:\n  - delay: 100ms\n  - write-serial: \"1\"\n  - delay: 6s\n"
        "  - expect-pose: { source: truth, x_m: ";
    std::ofstream(dir / "near.yaml") << "name: near\n" << steps << "0, y_m: 0, tol_m: 1 }\n";
    std::ofstream(dir / "far.yaml") << "name: far\n" << steps << "5, y_m: 0, tol_m: 0.01 }\n";
    const auto out = dir / "out";
    const auto sc = run_command(cli + " scenario " + sh_quote((dir / "near.yaml").string()) + " " +
                                sh_quote((dir / "far.yaml").string()) + " -j 2 --out " + sh_quote(out.string()));
    ASSERT_EQ(sc.exit_code, 1) << sc.out << sc.err;  // far fails its check
    const auto r = report_twice(out);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, (out / "near/report.md").string() + "\n" + (out / "far/report.md").string() + "\n" +
                         (out / "report.md").string() + "\n");
    const std::string index = read_text(out / "report.md");
    EXPECT_TRUE(has(index, "# ddmr-hil scenarios: 1 of 2 passed\n")) << index;
    EXPECT_TRUE(has(index, "| near | PASS | ")) << index;
    EXPECT_TRUE(has(index, "| far | FAIL | ")) << index;
    EXPECT_TRUE(has(index, "[far/report.md](far/report.md)")) << index;
    for (const char* name : {"near", "far"}) {
        for (const char* p : {"xy", "wheel_speeds", "drive", "currents", "battery"}) {
            EXPECT_TRUE(std::filesystem::exists(out / name / (std::string(p) + ".png"))) << name << " " << p;
            EXPECT_TRUE(std::filesystem::exists(out / name / (std::string(p) + ".svg"))) << name << " " << p;
        }
    }
    const std::string far = read_text(out / "far/report.md");
    EXPECT_TRUE(has(far, "# ddmr-hil scenario: far (FAIL)\n")) << far;
    EXPECT_TRUE(has(far, "| 7 | `{expect-pose: {source: truth, x_m: 5, y_m: 0, tol_m: 0.01}}` | 6.")) << far;
    EXPECT_TRUE(has(far, "| **FAILED** | expected the truth pose within 0.01 m of (5.0000, 0.0000)")) << far;
    EXPECT_TRUE(has(far, "![Motor currents](currents.png)\n\n*The motor currents, averaged over 25 PWM periods"))
        << far;
    EXPECT_TRUE(has(far, "The dotted lines are the steps' end times")) << far;
    EXPECT_TRUE(has(far, "- Tracking error: a scenario has no goal trajectory")) << far;
    EXPECT_TRUE(has(far, "`failure_window.vcd`")) << far;
    EXPECT_TRUE(has(read_text(out / "near/report.md"), "# ddmr-hil scenario: near (PASS)\n"));

    // One scenario's sub-folder on its own: the same report.
    const std::string near_md = read_text(out / "near/report.md");
    const auto one = run_command(cli + " report " + sh_quote((out / "near").string()));
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_EQ(one.out, (out / "near/report.md").string() + "\n");
    EXPECT_EQ(read_text(out / "near/report.md"), near_md);
}

TEST(MakeReport, TheCommandRefusesAnotherCommandsFolderInOneLine) {
    TempDir dir;
    std::filesystem::create_directories(dir / "calib");
    std::ofstream(dir / "calib" / "calibration.json") << "{}";
    const std::string cli = sh_quote(cli_path().string());
    const auto r = run_command(cli + " report " + sh_quote((dir / "calib").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_TRUE(has(r.err, "calib: a `ddmr-hil calibrate` output folder; report takes the output folder of "
                           "`ddmr-hil run`, `profile`, `sim` or `scenario` (or one scenario's sub-folder) (a "
                           "calibration writes its own report.md)"))
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    const auto empty = run_command(cli + " report " + sh_quote(dir.path().string()));
    EXPECT_EQ(empty.exit_code, 2);
    EXPECT_TRUE(has(empty.err, "a folder without ddmr-hil's outputs")) << empty.err;
}

TEST(MakeReport, MissingRunIsAnErrorNamingIt) {
    TempDir dir;
    const auto r = run_command("/usr/bin/python3 " + script() + " " + sh_quote((dir / "none").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("none"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace ddmr::test
