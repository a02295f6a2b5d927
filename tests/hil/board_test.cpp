// Board: the Uno wiring as data, its checks, and its YAML form.
#include "hil/board.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "plant/params_yaml.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

std::string load_error(const std::string& yaml) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << yaml;
    try {
        (void)hil::load_board_section(dir / "b.yaml");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(Board, DefaultIsTheThesisRobot) {
    const auto b = hil::uno_default_board();
    EXPECT_EQ(b.motor[0].enable_pin, 10);
    EXPECT_EQ(b.motor[0].direction_pin, 12);
    EXPECT_EQ(b.motor[1].enable_pin, 11);
    EXPECT_EQ(b.motor[1].direction_pin, 13);
    EXPECT_EQ(b.encoder[0].pin, 2);
    EXPECT_EQ(b.encoder[1].pin, 3);
    EXPECT_NO_THROW(hil::validate(b, "default"));
}

TEST(Board, UnoPinsMapToTheirPortBits) {
    // Uno schematic: D0-D7 = PD0-PD7, D8-D13 = PB0-PB5, A0-A5 = PC0-PC5.
    EXPECT_EQ(hil::uno_pin_location(2)->port, 'D');
    EXPECT_EQ(hil::uno_pin_location(2)->bit, 2);
    EXPECT_EQ(hil::uno_pin_location(10)->port, 'B');
    EXPECT_EQ(hil::uno_pin_location(10)->bit, 2);
    EXPECT_EQ(hil::uno_pin_location(13)->bit, 5);
    EXPECT_EQ(hil::uno_pin_location(14)->port, 'C');
    EXPECT_FALSE(hil::uno_pin_location(20).has_value());
    EXPECT_FALSE(hil::uno_pin_location(-1).has_value());
    EXPECT_STREQ(hil::uno_pwm_channel(10)->name, "OC1B");
    EXPECT_STREQ(hil::uno_pwm_channel(11)->name, "OC2A");
    EXPECT_FALSE(hil::uno_pwm_channel(5).has_value());  // Timer0: fast PWM
    EXPECT_EQ(*hil::uno_external_interrupt(3), 1);
    EXPECT_FALSE(hil::uno_external_interrupt(4).has_value());
}

TEST(Board, InvalidWiringsAreRefusedNamingThePin) {
    auto b = hil::uno_default_board();
    b.motor[0].enable_pin = 12;  // also motor 1's direction pin, and not PWM
    EXPECT_THROW(hil::validate(b, "x"), std::invalid_argument);
    b = hil::uno_default_board();
    b.encoder[1].pin = 2;
    try {
        hil::validate(b, "x");
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("already used by board.encoder1.pin"), std::string::npos) << e.what();
    }
    b = hil::uno_default_board();
    b.motor[1].direction_pin = 25;
    EXPECT_THROW(hil::validate(b, "x"), std::invalid_argument);
    b = hil::uno_default_board();
    b.motor[1].enable_pin = 6;
    EXPECT_THROW(hil::validate(b, "x"), std::invalid_argument);
}

TEST(Board, YamlSectionOverridesTheDefaults) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << "board:\n  encoder1: {pin: 3}\n  encoder2: {pin: 2}\n";
    const auto b = hil::load_board_section(dir / "b.yaml");
    ASSERT_TRUE(b.has_value());
    EXPECT_EQ(b->encoder[0].pin, 3);
    EXPECT_EQ(b->encoder[1].pin, 2);
    EXPECT_EQ(b->motor[0].enable_pin, 10);
}

TEST(Board, FileWithoutBoardSectionHasNone) {
    TempDir dir;
    std::ofstream(dir / "p.yaml") << "battery:\n  capacity_Ah: 2.5\n";
    EXPECT_FALSE(hil::load_board_section(dir / "p.yaml").has_value());
}

TEST(Board, PlantFileMayCarryTheBoard) {
    // One file for robot and wiring: the plant loader leaves `board` to us.
    TempDir dir;
    std::ofstream(dir / "robot.yaml") << "board:\n  motor1: {enable_pin: 9, direction_pin: 8}\n";
    EXPECT_NO_THROW((void)plant::load_robot_params(dir / "robot.yaml"));
    EXPECT_EQ(hil::load_board_section(dir / "robot.yaml")->motor[0].enable_pin, 9);
}

TEST(Board, BadYamlIsRefusedWithFileLineAndKey) {
    EXPECT_NE(load_error("board:\n  motor3: {enable_pin: 9}\n").find("unknown key board.motor3"), std::string::npos);
    EXPECT_NE(load_error("board:\n  motor1: {enable: 9}\n").find("board.motor1.enable"), std::string::npos);
    const auto msg = load_error("board:\n  encoder1: {pin: two}\n");
    EXPECT_NE(msg.find("b.yaml:2:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'two'"), std::string::npos) << msg;
    EXPECT_NE(load_error("board:\n  encoder1: {pin: 99}\n").find("99"), std::string::npos);
    EXPECT_NE(load_error("board: [1, 2\n").find("malformed YAML"), std::string::npos);
}

}  // namespace
}  // namespace ddmr::test
