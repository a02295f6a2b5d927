// `ddmr-hil calibrate` through the binary (tools/calibrate_command.cpp): the
// outputs the issue names (plant.yaml loadable with --plant, calibration.json
// with train / holdout / before, report.md with its plots, the HIL
// confirmation), byte-identical reruns, and refused input (exit 2, one line,
// nothing written). The fits here are tiny (budgets of a few evaluations):
// whether a calibration converges is calibration_test.cpp's subject.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "plant/params_yaml.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

std::string cli() { return sh_quote(DDMR_TEST_CLI); }

/// The synthetic robot's case-1 dump, made once by the HIL.
const fs::path& robot_log() {
    static TempDir dir;
    static const fs::path log = [] {
        const fs::path plant = source_dir() / "tests/tools/calibrate/data/perturbed_robot.yaml";
        const ProcessResult r = run_command(cli() + " run --case 1 -q --plant " + sh_quote(plant.string()) + " --out " +
                                            sh_quote((dir / "robot").string()));
        EXPECT_EQ(r.exit_code, 0) << r.err;
        return dir / "robot" / "uart.txt";
    }();
    return log;
}

const std::string kTiny = " --fit motor1.resistance_ohm --lm-evals 6 --local-evals 3 --phases 1 -q";

TEST(CalibrateCommand, WritesThePlantTheScoresTheReportAndConfirmsInTheHil) {
    TempDir dir;
    const fs::path out = dir / "cal";
    const ProcessResult r = run_command(cli() + " calibrate " + sh_quote(robot_log().string()) + " --split 0.5" + kTiny +
                                        " --out " + sh_quote(out.string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("motor1.resistance_ohm"), std::string::npos) << r.out;

    // plant.yaml loads as a plant file and says where the value came from.
    const std::string yaml = read_text(out / "plant.yaml");
    EXPECT_NE(yaml.find("resistance_ohm: "), std::string::npos);
    EXPECT_NE(yaml.find("# fitted (start 5.32): interval ["), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("uart.txt [0, 60)"), std::string::npos) << yaml;
    const plant::RobotParams p = plant::load_robot_params(out / "plant.yaml");

    const auto j = nlohmann::json::parse(read_text(out / "calibration.json"));
    EXPECT_DOUBLE_EQ(j["params"][0]["value"].get<double>(), p.motor[0].resistance_ohm);
    for (const auto* part : {&j["train"], &j["holdout"], &j["before"]["train"], &j["before"]["holdout"]}) {
        for (const char* k : {"rms_m", "max_m", "endpoint_m", "endpoint_pct", "samples"}) {
            EXPECT_TRUE((*part)[k].is_number()) << k << " in " << part->dump();
        }
    }
    EXPECT_EQ(j["train"]["samples"], 60);
    EXPECT_EQ(j["holdout"]["samples"], 60);
    EXPECT_TRUE(j["train"]["count1"].is_null());  // the fitted half does not reach the totals
    EXPECT_TRUE(j["holdout"]["count1"].is_number());
    EXPECT_EQ(j["holdout"]["logged_count1"].get<uint64_t>() > 0, true);
    EXPECT_EQ(j["hil"]["exit"], "report_complete");
    EXPECT_EQ(j["logs"]["train"][0]["end"], 60);
    EXPECT_EQ(j["logs"]["holdout"][0]["first"], 60);
    EXPECT_TRUE(j["warnings"].is_array());
    EXPECT_TRUE(fs::exists(out / "hil" / "uart.txt"));

    const std::string md = read_text(out / "report.md");
    EXPECT_NE(md.find("| `motor1.resistance_ohm` | 5.32 |"), std::string::npos) << md;
    EXPECT_NE(md.find("![split: fitted, then judged](xy_1_robot.svg)"), std::string::npos) << md;
    EXPECT_EQ(read_text(out / "xy_1_robot.svg").rfind("<svg ", 0), 0U);
    EXPECT_EQ(read_text(out / "tracks.csv").rfind("log,sample,logged_x_m,logged_y_m,before_x_m,", 0), 0U);
}

// The second run names the log by its folder (a `run` output folder): the same log, the same outputs.
TEST(CalibrateCommand, RerunIsByteIdentical) {
    TempDir dir;
    for (const char* sub : {"a", "b"}) {
        const fs::path log = sub[0] == 'a' ? robot_log() : robot_log().parent_path();
        const ProcessResult r = run_command(cli() + " calibrate " + sh_quote(log.string()) + kTiny +
                                            " --no-hil --out " + sh_quote((dir / sub).string()));
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_EQ(file_tree(dir / "a"), file_tree(dir / "b"));
}

/// The robot's dump cut short: its first 9 lines (banner, END, the counts,
/// the report), no addr, then the first `samples` dump lines and one more
/// (the unwritten byte).
std::string cut_dump(std::size_t samples) {
    std::istringstream in(read_text(robot_log()));
    std::string out;
    std::size_t n = 0;
    for (std::string line; std::getline(in, line); ++n) {
        if (n < 9 || (n >= 10 && n < 10 + samples + 1)) out += line + "\n";
    }
    return out;
}

/// The robot's dump without its last `lines` lines.
std::string without_last_lines(std::size_t lines) {
    std::string text = read_text(robot_log());
    for (std::size_t k = 0; k < lines; ++k) text.resize(text.rfind('\n', text.size() - 2) + 1);
    return text;
}

// Issue 32: a dump pasted from a serial monitor often lacks its last line
// (the byte at addr, which the firmware never wrote). The HIL's case-1 dump
// (addr 240: 121 lines) without it has 120: read as the same 120 samples,
// the same fit, and said in one line on stderr and in calibration.json.
TEST(CalibrateCommand, ADumpWithoutItsUnwrittenLastLineIsReadAndSaidSo) {
    TempDir dir;
    const fs::path cut = dir / "pasted.txt";
    std::ofstream(cut) << without_last_lines(1);
    const std::string args = kTiny + " --split 0.5 --no-hil --out ";
    const ProcessResult whole = run_command(cli() + " calibrate " + sh_quote(robot_log().string()) + args +
                                            sh_quote((dir / "whole").string()));
    ASSERT_EQ(whole.exit_code, 0) << whole.err;
    const ProcessResult r = run_command(cli() + " calibrate " + sh_quote(cut.string()) + args +
                                        sh_quote((dir / "pasted").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string warning = cut.string() + ": addr 240 promises 121 dump lines, the file has 120: read as the dump "
                                "without its last line (the byte at addr, which the run never wrote), 120 logged samples";
    EXPECT_EQ(r.err, "ddmr-hil calibrate: warning: " + warning + "\n");  // -q: nothing else
    EXPECT_TRUE(whole.err.empty()) << whole.err;
    const auto j = nlohmann::json::parse(read_text(dir / "pasted" / "calibration.json"));
    const auto w = nlohmann::json::parse(read_text(dir / "whole" / "calibration.json"));
    ASSERT_TRUE(j["warnings"].is_array());
    ASSERT_FALSE(j["warnings"].empty());
    EXPECT_EQ(j["warnings"][0], warning);
    EXPECT_EQ(j["warnings"].size(), w["warnings"].size() + 1);
    EXPECT_EQ(j["train"]["samples"], 60);
    EXPECT_EQ(j["holdout"]["samples"], 60);
    EXPECT_EQ(j["params"], w["params"]);  // the same samples, the same fit
    EXPECT_NE(read_text(dir / "pasted" / "report.md").find("- " + warning + "\n"), std::string::npos);
}

TEST(CalibrateCommand, RefusedInputIsOneLineExitTwoAndWritesNothing) {
    TempDir dir;
    const fs::path bad_log = dir / "bad.txt";
    {
        std::ofstream(bad_log) << "0.6m\n1 , 2\n";
        std::ofstream(dir / "cut.txt") << cut_dump(50);
        std::ofstream(dir / "two_short.txt") << without_last_lines(2);
    }
    const std::string log = sh_quote(robot_log().string());
    const struct {
        std::string args;
        std::string message;
    } cases[] = {
        {log + " --fit kinematics.wheel_radius_right_m",
         "--fit kinematics.wheel_radius_right_m: the log does not depend on it"},
        {log + " --fit motor1.nonsense", "--fit motor1.nonsense: not a real-valued plant parameter"},
        {log + " --split 1.5", "--split 1.5: not in (0, 1)"},
        {log + " --case 2", "its banner says case 1, --case says 2"},
        {log + " --split 0.5 --hold-out " + log, "--split and --hold-out: give one of them"},
        {sh_quote(bad_log.string()), "bad.txt"},
        {sh_quote(dir.path().string()), "a folder without uart.txt"},
        {log + " --hold-out " + log, "given twice (a held-out log must not be a fitted one)"},
        {log + " --case 0", "--case 0: the sketch has cases 1 and 2 only"},
        {sh_quote((dir / "cut.txt").string()), "cut.txt: 50 logged samples; case 1 logs 120 (one per 0.1 s)"},
        {sh_quote((dir / "two_short.txt").string()), "two_short.txt: addr 240 promises 121 dump lines, the file has 119"},
        {log + " --firmware " + log, "uart.txt"},  // not an ELF: refused before the fit
        {log + " --seed -1", "--seed -1: must be >= 0"},
        {log + " --period-ms 2000", "--period-ms 2000: must be in [0.1, 1000] ms"},
        {log + " " + log, "uart.txt: given twice\n"},
    };
    for (const auto& c : cases) {
        const fs::path out = dir / "out";
        const ProcessResult r = run_command(cli() + " calibrate " + c.args + " --phases 1 -q --out " + sh_quote(out.string()));
        EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(out)) << c.args;
    }
}

}  // namespace
}  // namespace ddmr::test
