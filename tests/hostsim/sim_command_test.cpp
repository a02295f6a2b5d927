// `ddmr-hil sim` through the binary (tools/sim_command.cpp): outputs, option
// errors (exit 2, nothing written) and byte-identical reruns.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

std::string cli() { return sh_quote(DDMR_TEST_CLI); }

TEST(SimCommand, WritesSimCsvEepromLogAndSummary) {
    TempDir dir;
    const ProcessResult r =
        run_command(cli() + " sim --model firmware --duration 1 --out " + sh_quote((dir / "a").string()));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string csv = read_text(dir / "a" / "sim.csv");
    EXPECT_EQ(csv.rfind("t_s,x_m,y_m,theta_rad,v_m_s,omega_rad_s,ia1_A,ia2_A,wheel1_rad_s,wheel2_rad_s,vbatt_V,"
                        "edges1,edges2,duty1,duty2,dir1,dir2,goal_x_m,goal_y_m,lyapunov\n",
                        0),
              0U);
    const std::string log = read_text(dir / "a" / "eeprom_log.csv");
    EXPECT_EQ(log.rfind("sample,t_s,x_m,y_m\n0,0.100000,", 0), 0U) << log;
    const std::string summary = read_text(dir / "a" / "summary.json");
    EXPECT_NE(summary.find("\"model\": \"firmware\""), std::string::npos);
    EXPECT_NE(summary.find("\"wall_time_s\""), std::string::npos);
}

TEST(SimCommand, RerunIsByteIdentical) {
    TempDir dir;
    for (const char* sub : {"a", "b"}) {
        const ProcessResult r = run_command(cli() + " sim --model firmware --duration 2 --out " +
                                            sh_quote((dir / sub).string()));
        ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    EXPECT_EQ(read_text(dir / "a" / "sim.csv"), read_text(dir / "b" / "sim.csv"));
    EXPECT_EQ(read_text(dir / "a" / "eeprom_log.csv"), read_text(dir / "b" / "eeprom_log.csv"));
}

TEST(SimCommand, DefaultOutputFolderNamesCaseAndModel) {
    TempDir dir;
    const ProcessResult r =
        run_command("cd " + sh_quote(dir.path().string()) + " && " + cli() + " sim --case 2 --duration 0.5");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out/sim-case2-ideal/sim.csv"));
}

TEST(SimCommand, BadOptionsExit2NamingTheValueAndWriteNothing) {
    TempDir dir;
    const std::string out = " --out " + sh_quote((dir / "x").string());
    expect_refused(cli() + " sim ", out, dir / "x",
                   {BadArgs{"--fidelity int_gains,warp_drive", "warp_drive"},
                    BadArgs{"--model firmware --fidelity float32", "--fidelity"},
                    BadArgs{"--circle 0,12", "--circle"},
                    BadArgs{"--case 3", "--case"},
                    BadArgs{"--case 1 --line x", "--line"},
                    BadArgs{"--kx -1", "--kx"},
                    BadArgs{"--plant kinematic --fidelity encoder_odometry", "encoder_odometry"},
                    BadArgs{"--plant /no/such.yaml", "/no/such.yaml"},
                    BadArgs{"--model firmware --duration 0.005", "--duration"}});
}

}  // namespace
}  // namespace ddmr::test
