// Tests for plant/params_yaml: the documented default file equals the embedded
// defaults, emit/parse round-trips exactly, and every kind of bad file is
// rejected with one line naming the file, the line, the key and the value.
#include "plant/params_yaml.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace ddmr::plant {
namespace {

/// what() of the ParamsFileError thrown by parsing `text` (fails if none).
std::string error_of(const std::string& text) {
    try {
        parse_robot_params(text, "bad.yaml");
    } catch (const ParamsFileError& e) {
        const std::string msg = e.what();
        EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
        return msg;
    }
    ADD_FAILURE() << "accepted:\n" << text;
    return {};
}

TEST(ParamsYaml, DefaultFileEqualsEmbeddedDefaults) {
    const RobotParams from_file = load_robot_params(DDMR_PLANT_DEFAULT_YAML);
    EXPECT_TRUE(from_file == default_robot_params());
}

TEST(ParamsYaml, EmitThenParseRoundTripsExactly) {
    RobotParams p = default_robot_params();
    p.motor[0].inductance_H = 1.0 / 3.0;  // needs all 17 digits
    p.battery.open_circuit_V = 5.987654321;
    p.encoder[1].seed = 18446744073709551615ULL;
    p.encoder[0].edges_per_motor_rev = 16;
    const RobotParams back = parse_robot_params(emit_robot_params(p), "emitted");
    EXPECT_TRUE(back == p);
    EXPECT_FALSE(back == default_robot_params());  // the comparison can fail
}

TEST(ParamsYaml, SaveThenLoadRoundTrips) {
    const auto path = std::filesystem::temp_directory_path() / "ddmr_plant_params_test.yaml";
    RobotParams p = default_robot_params();
    p.kinematics.half_axle_m = 0.0635;  // the firmware's 1/(2 x 7.874)
    save_robot_params(p, path);
    EXPECT_TRUE(load_robot_params(path) == p);
    std::filesystem::remove(path);
}

TEST(ParamsYaml, PartialFileOverridesOnlyItsKeys) {
    const RobotParams p = parse_robot_params("driver:\n  drop_V: 0.5\n", "partial.yaml");
    RobotParams expected = default_robot_params();
    expected.driver.drop_V = 0.5;
    EXPECT_TRUE(p == expected);
    EXPECT_TRUE(parse_robot_params("", "empty.yaml") == default_robot_params());
}

TEST(ParamsYaml, EachChipHasItsSection) {
    const RobotParams p = parse_robot_params(
        "tb6612:\n  on_resistance_ohm: 0.7\ndrv8833:\n  flyback_diode_drop_V: 0.9\n"
        "l293d:\n  drop_V: 3.6\n",
        "chips.yaml");
    RobotParams expected = default_robot_params();
    expected.tb6612.on_resistance_ohm = 0.7;
    expected.drv8833.flyback_diode_drop_V = 0.9;
    expected.l293d.drop_V = 3.6;  // the L293D's worst case, 1.8 + 1.8 V
    EXPECT_TRUE(p == expected);
    EXPECT_EQ(p.driver.drop_V, 1.4);  // `driver:` is the L298, untouched
}

TEST(ParamsYaml, EdgesPerWheelRevReplacesTheDefaultEdgesPerMotorRev) {
    // Also after another key of the section: the section is consistent at every key.
    const RobotParams p = parse_robot_params(
        "encoder1:\n  initial_phase: 0.25\n  edges_per_wheel_rev: 40\n", "wheel.yaml");
    EXPECT_EQ(p.encoder[0].edges_per_motor_rev, 0);
    EXPECT_EQ(p.encoder[0].edges_per_wheel_rev, 40.0);
    EXPECT_EQ(p.encoder[0].initial_phase, 0.25);
    EXPECT_EQ(p.encoder[1].edges_per_motor_rev, 8);  // the other encoder keeps its default
    // It round-trips: the emitter writes only the resolution key in use.
    EXPECT_TRUE(parse_robot_params(emit_robot_params(p), "emitted") == p);
    EXPECT_EQ(emit_robot_params(p).find("edges_per_motor_rev: 0"), std::string::npos);
}

TEST(ParamsYaml, BothResolutionKeysInOneEncoderAreRejectedNamingBoth) {
    EXPECT_EQ(error_of("encoder2:\n  edges_per_motor_rev: 8\n  seed: 3\n  edges_per_wheel_rev: 40\n"),
              "bad.yaml:4:3: encoder2.edges_per_motor_rev (line 2) and encoder2.edges_per_wheel_rev "
              "(line 4) are alternatives: give only one of them");
    EXPECT_NE(error_of("encoder1:\n  edges_per_wheel_rev: 39\n").find(
                  "bad.yaml:2:24: encoder1.edges_per_wheel_rev: invalid value '39'"),
              std::string::npos);
}

TEST(ParamsYaml, UnknownKeyNamesFileLineAndKey) {
    EXPECT_EQ(error_of("motor1:\n  resistance_ohm: 5.0\n  resistnce_ohm: 5.0\n"),
              "bad.yaml:3:3: unknown key 'motor1.resistnce_ohm'");
    EXPECT_NE(error_of("motor3:\n  resistance_ohm: 5.0\n").find("bad.yaml:1:1: unknown key 'motor3'"),
              std::string::npos);
}

TEST(ParamsYaml, InvalidValuesNameKeyAndValue) {
    EXPECT_EQ(error_of("motor2:\n  resistance_ohm: -1\n"),
              "bad.yaml:2:19: motor2.resistance_ohm: invalid value '-1': must be finite and in "
              "(0, 1000] ohm");
    EXPECT_EQ(error_of("battery:\n  capacity_Ah: .nan\n"),
              "bad.yaml:2:16: battery.capacity_Ah: invalid value '.nan': must be finite and in "
              "(0, 100] Ah");
    EXPECT_EQ(error_of("driver:\n  drop_V: abc\n"),
              "bad.yaml:2:11: driver.drop_V: invalid value 'abc': not a number [V]");
    EXPECT_EQ(error_of("encoder1:\n  edges_per_motor_rev: 7\n").rfind(
                  "bad.yaml:2:24: encoder1.edges_per_motor_rev: invalid value '7': ", 0),
              0u);
    EXPECT_NE(error_of("encoder1:\n  edges_per_motor_rev: 8.5\n").find("not an integer"),
              std::string::npos);
    EXPECT_NE(error_of("encoder2:\n  seed: -3\n").find("encoder2.seed: invalid value '-3'"),
              std::string::npos);
    EXPECT_NE(error_of("kinematics:\n  half_axle_m: [1, 2]\n").find("kinematics.half_axle_m"),
              std::string::npos);
    EXPECT_NE(error_of("kinematics: 3\n").find("kinematics: expected a mapping"), std::string::npos);
}

TEST(ParamsYaml, MalformedYamlNamesTheLine) {
    const std::string msg = error_of("motor1:\n  resistance_ohm: [5.0\n");
    EXPECT_EQ(msg.rfind("bad.yaml:", 0), 0u) << msg;
    EXPECT_NE(msg.find("malformed YAML"), std::string::npos) << msg;
}

TEST(ParamsYaml, MissingFileNamesIt) {
    try {
        load_robot_params("/nonexistent/plant.yaml");
        FAIL();
    } catch (const ParamsFileError& e) {
        EXPECT_EQ(std::string(e.what()),
                  "/nonexistent/plant.yaml: cannot read plant parameter file: No such file or "
                  "directory");
    }
}

}  // namespace
}  // namespace ddmr::plant
