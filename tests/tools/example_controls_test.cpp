// The examples' negative controls (issue 33): each example robot miswired as
// a user might wire it must fail its own scenario's checks. The passing runs
// are the example_scenarios test (tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "support/scenario_cli.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

struct Control {
    const char* file;          ///< under firmware/examples/
    const char* name;          ///< its scenario name
    const char* failing_kind;  ///< the step that must fail
    const char* message;       ///< a part of the failing step's message
};

class ExampleControl : public ::testing::TestWithParam<Control> {};

/// The test's name: the scenario's, as gtest allows it (letters, digits, _).
std::string control_name(const ::testing::TestParamInfo<Control>& p) {
    std::string n = p.param.name;
    for (char& ch : n) {
        if (std::isalnum(static_cast<unsigned char>(ch)) == 0) ch = '_';
    }
    return n;
}

TEST_P(ExampleControl, FailsItsScenario) {
    const Control& c = GetParam();
    TempDir dir;
    const ProcessResult r = scenario(sh_quote((source_dir() / "firmware/examples" / c.file).string()) + " --out " +
                                     sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const nlohmann::json j = result_of(dir / "out" / c.name);
    EXPECT_EQ(j["verdict"], "fail");
    const nlohmann::json& last = j["steps"].back();
    EXPECT_FALSE(last["passed"].get<bool>());
    EXPECT_EQ(last["kind"], c.failing_kind);
    EXPECT_NE(last["message"].get<std::string>().find(c.message), std::string::npos) << last["message"];
}

INSTANTIATE_TEST_SUITE_P(
    Examples, ExampleControl,
    ::testing::Values(
        // The two line sensors' pins swapped: the sketch steers away from the line.
        Control{"line_follower_digital/scenario_swapped.yaml", "line_follower_digital_swapped", "expect-stats",
                "expected rms <= 0.003; row_middle.line_offset_m over 3000 samples"},
        // The sonar's TRIG and ECHO swapped: no echo ever, the car drives into the wall.
        Control{"obstacle_avoider_servo/scenario_swapped.yaml", "obstacle_avoider_servo_swapped", "wait-serial",
                "expected 'stop ' within 4.000 s"},
        // The MPU-6050 upside down (the Z gyro's sign flipped): positive feedback, it spins away.
        Control{"heading_hold_mpu6050/scenario_flipped.yaml", "heading_hold_mpu6050_flipped", "wait-until",
                "expected theta_rad < 0.035 within 1.500 s"}),
    control_name);

}  // namespace
}  // namespace ddmr::test
