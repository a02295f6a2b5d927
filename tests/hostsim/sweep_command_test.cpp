// `ddmr-hil sweep` through the binary (tools/sweep_command.cpp): the same
// bytes with -j 1 and -j 2 (data and plots), progress on stderr, option
// errors (exit 2, one line naming the value, nothing written).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

std::string cli() { return sh_quote(DDMR_TEST_CLI); }

// fig5_8 is the cheapest study (two runs, 8 s and 12 s) on the motor plant.
TEST(SweepCommand, OneAndTwoWorkersWriteTheSameBytes) {
    TempDir dir;
    const ProcessResult a =
        run_command(cli() + " sweep --study fig5_8 -j 1 --quiet --out " + sh_quote((dir / "a").string()));
    ASSERT_EQ(a.exit_code, 0) << a.err;
    EXPECT_EQ(a.err, "");  // --quiet
    const ProcessResult b = run_command(cli() + " sweep --study fig5_8 -j 2 --out " + sh_quote((dir / "b").string()));
    ASSERT_EQ(b.exit_code, 0) << b.err;
    EXPECT_NE(b.err.find("sweep: fig5_8 done (1/1 studies)"), std::string::npos) << b.err;

    for (const char* f : {"fig5_8.csv", "sweep.json", "fig5_8.svg", "fig5_8.png"}) {
        const std::string bytes = read_text(dir / "a" / f);
        EXPECT_FALSE(bytes.empty()) << f;
        EXPECT_EQ(bytes, read_text(dir / "b" / f)) << f;
    }
    const std::string csv = read_text(dir / "a" / "fig5_8.csv");
    EXPECT_EQ(csv.rfind("case,gain_value,t_s,x_m,y_m,theta_rad,goal_x_m,goal_y_m,error_m,xe_m,ye_m,v_m_s,"
                        "omega_rad_s\ncircle-0.4m-8s,,0.00,0.000000,0.000000,0.000000,0.400000,0.000000,0.400000,",
                        0),
              0U)
        << csv.substr(0, 300);
    // 801 + 1201 rows at 100 Hz, and the header.
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 801 + 1201);
    const std::string json = read_text(dir / "a" / "sweep.json");
    EXPECT_NE(json.find("\"id\": \"fig5_8\""), std::string::npos);
    EXPECT_NE(json.find("\"rms_error_m\""), std::string::npos);
    EXPECT_EQ(json.find("wall"), std::string::npos);  // no wall time in the files
}

TEST(SweepCommand, NoPlotWritesDataOnly) {
    TempDir dir;
    const ProcessResult r = run_command(cli() + " sweep --study fig5_8 --plant kinematic --no-plot -q --out " +
                                        sh_quote((dir / "a").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "a" / "fig5_8.csv"));
    EXPECT_TRUE(std::filesystem::exists(dir / "a" / "sweep.json"));
    EXPECT_FALSE(std::filesystem::exists(dir / "a" / "fig5_8.png"));
    EXPECT_NE(read_text(dir / "a" / "sweep.json").find("\"plant\": \"kinematic\""), std::string::npos);
}

TEST(SweepCommand, BadOptionsExit2NamingTheValueAndWriteNothing) {
    TempDir dir;
    const std::string out = " --out " + sh_quote((dir / "x").string());
    expect_refused(cli() + " sweep ", out, dir / "x",
                   {BadArgs{"--study fig5_2,fig9_9", "fig9_9"},
                    BadArgs{"--study fig5_2,", "--study"},
                    BadArgs{"-j 0", "-j"},
                    BadArgs{"--model warp", "warp"},
                    BadArgs{"--model firmware --plant kinematic", "--plant kinematic"},
                    BadArgs{"--plant /no/such.yaml", "/no/such.yaml"}});
}

}  // namespace
}  // namespace ddmr::test
