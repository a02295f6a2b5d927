// Board: the robot's wiring as data, its checks, and its file form.
#include "hil/board.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <string>

#include "support/board_file.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using hil::DriverRole;

std::string load_error(const std::string& yaml) { return board_load_error(yaml); }

hil::BoardWiring load(const std::string& yaml) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << yaml;
    return hil::load_board_file(dir / "b.yaml");
}

bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(Board, DefaultIsTheThesisRobotAndEqualsTheShippedFile) {
    const auto b = hil::default_board();
    EXPECT_EQ(b.wheel[0].motor.driver, plant::DriverType::dir_pwm);
    EXPECT_EQ(b.wheel[0].motor[DriverRole::pwm].pin, 10);
    EXPECT_EQ(b.wheel[0].motor[DriverRole::dir].pin, 12);
    EXPECT_EQ(b.wheel[1].motor[DriverRole::pwm].pin, 11);
    EXPECT_EQ(b.wheel[1].motor[DriverRole::dir].pin, 13);
    EXPECT_EQ(b.wheel[0].encoder.pin[0], 2);
    EXPECT_EQ(b.wheel[1].encoder.pin[0], 3);
    const auto f = hil::load_board_file(source_dir() / "firmware/ddmr_tracking/board.yaml");
    for (std::size_t m = 0; m < 2; ++m) {
        EXPECT_EQ(f.wheel[m].motor.driver, b.wheel[m].motor.driver);
        for (std::size_t r = 0; r < hil::kDriverRoleCount; ++r) {
            EXPECT_EQ(f.wheel[m].motor.input[r].used, b.wheel[m].motor.input[r].used) << m << r;
            EXPECT_EQ(f.wheel[m].motor.input[r].pin, b.wheel[m].motor.input[r].pin) << m << r;
            EXPECT_EQ(f.wheel[m].motor.input[r].tied_high, b.wheel[m].motor.input[r].tied_high) << m << r;
        }
        EXPECT_EQ(f.wheel[m].encoder.kind, b.wheel[m].encoder.kind);
        EXPECT_EQ(f.wheel[m].encoder.pin, b.wheel[m].encoder.pin);
        EXPECT_EQ(f.wheel[m].motor.reversed, b.wheel[m].motor.reversed);
    }
}

TEST(Board, EveryDriverTypeAndEncoderTypeLoads) {
    const auto b = load(
        "board: nano\n"
        "wheels:\n"
        "  left:\n"
        "    motor:   {driver: l298n, EN: high, IN1: 7, IN2: A1, reversed: true}\n"
        "    encoder: {type: quadrature, A: 2, B: A4, reversed: true}\n"
        "  right:\n"
        "    motor:   {driver: tb6612, PWM: 9, IN1: 8, IN2: 4, STBY: high}\n"
        "    encoder: {type: single, OUT: 3}\n");
    EXPECT_EQ(b.model, hil::BoardModel::nano);
    const auto& left = b.wheel[1];
    EXPECT_EQ(left.motor.driver, plant::DriverType::l298n);
    EXPECT_TRUE(left.motor[DriverRole::en].tied_high);
    EXPECT_EQ(left.motor[DriverRole::in2].pin, 15);
    EXPECT_TRUE(left.motor.reversed);
    EXPECT_EQ(left.encoder.kind, hil::EncoderKind::quadrature);
    EXPECT_EQ(left.encoder.pin[1], 18);
    EXPECT_TRUE(left.encoder.reversed);
    EXPECT_EQ(b.wheel[0].motor[DriverRole::stby].tied_high, true);
    EXPECT_EQ(hil::input_label(b, 1, DriverRole::in2), "left L298N IN2");
    // DRV8833: nSLEEP left out is pulled up on breakout boards.
    const auto d = load(
        "wheels:\n"
        "  left:  {motor: {driver: drv8833, IN1: 5, IN2: 6}, encoder: {type: single, OUT: 2}}\n"
        "  right: {motor: {driver: drv8833, IN1: 9, IN2: 10}, encoder: {type: single, OUT: 3}}\n");
    EXPECT_EQ(d.model, hil::BoardModel::uno);
    EXPECT_TRUE(d.wheel[0].motor[DriverRole::sleep].used);
    EXPECT_TRUE(d.wheel[0].motor[DriverRole::sleep].tied_high);
}

TEST(Board, AWheelWithoutEncoderDrivesNoPin) {
    // Many kit robots have no encoders: the key is optional.
    const auto b = load(
        "wheels:\n"
        "  left:  {motor: {driver: l298n, EN: 5, IN1: 7, IN2: 8}}\n"
        "  right: {motor: {driver: l298n, EN: 6, IN1: 9, IN2: 11}, encoder: {type: single, OUT: 2}}\n");
    EXPECT_EQ(b.wheel[1].encoder.kind, hil::EncoderKind::none);
    EXPECT_EQ(b.wheel[1].encoder.signals(), 0u);
    EXPECT_EQ(hil::wired_pins(b), (std::vector<int>{2, 5, 6, 7, 8, 9, 11}));
    const std::map<int, std::string> uses = hil::pin_uses(b);
    EXPECT_EQ(uses.at(2), "wheels.right.encoder.OUT");
    EXPECT_EQ(uses.at(5), "wheels.left.motor.EN");
    EXPECT_EQ(uses.at(11), "wheels.right.motor.IN2");
}

TEST(Board, ADualModulesSharedStandbyPinIsOneModuleNotAPinUsedTwice) {
    const std::string shared =
        "wheels:\n"
        "  left:  {motor: {driver: tb6612, PWM: 5, IN1: 7, IN2: 8, STBY: 4}, encoder: {type: single, OUT: 2}}\n"
        "  right: {motor: {driver: tb6612, PWM: 6, IN1: 9, IN2: 12, STBY: 4}, encoder: {type: single, OUT: 3}}\n";
    EXPECT_EQ(load_error(shared), "");
    // ...but not another input on that pin.
    const std::string clash =
        "wheels:\n"
        "  left:  {motor: {driver: tb6612, PWM: 5, IN1: 7, IN2: 8, STBY: 4}, encoder: {type: single, OUT: 2}}\n"
        "  right: {motor: {driver: tb6612, PWM: 6, IN1: 4, IN2: 12, STBY: 9}, encoder: {type: single, OUT: 3}}\n";
    const std::string msg = load_error(clash);
    EXPECT_TRUE(contains(msg, "b.yaml:2: key 'wheels.left.motor.STBY': pin 4 is already used by wheels.right.motor.IN1"))
        << msg;
}

TEST(Board, MistakesAreOneLineWithFileLineAndKey) {
    const std::string head = "wheels:\n  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n";
    // Unknown driver type.
    std::string m = load_error(head + "  left:\n    motor: {driver: l293, EN: 5}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "b.yaml:4: key 'wheels.left.motor.driver': unknown driver 'l293'")) << m;
    // Missing input.
    m = load_error(head + "  left:\n    motor: {driver: l298n, EN: 5, IN1: 7}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "key 'wheels.left.motor.IN2': missing")) << m;
    // An input the driver does not have.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 13, EN: 5}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "key 'wheels.left.motor.EN': unknown key")) << m;
    // A pin the board lacks.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: A7}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "b.yaml:4: key 'wheels.left.motor.DIR'")) << m;
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 25}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "'25' is not a pin")) << m;
    // A pin used twice.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 13}\n    encoder: {type: single, OUT: 2}\n");
    EXPECT_TRUE(contains(m, "b.yaml:5: key 'wheels.left.encoder.OUT': pin 2 is already used by wheels.right.encoder.OUT"))
        << m;
    // PWM on a pin without a timer output.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 4, DIR: 13}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "key 'wheels.left.motor.PWM': pin 4 has no timer output")) << m;
    // `high` where the module has no jumper.
    m = load_error(head + "  left:\n    motor: {driver: l298n, EN: 5, IN1: high, IN2: 6}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "key 'wheels.left.motor.IN1': the L298N input IN1 must be wired to a pin")) << m;
    // The UART pins.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 1}\n    encoder: {type: single, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "pin 1 carries Serial's TX (pins 0 and 1, the USB serial port, cannot be wired)")) << m;
    // Unknown encoder type, missing B.
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 13}\n    encoder: {type: optical, OUT: 3}\n");
    EXPECT_TRUE(contains(m, "b.yaml:5: key 'wheels.left.encoder.type': unknown encoder type 'optical'")) << m;
    m = load_error(head + "  left:\n    motor: {driver: dir-pwm, PWM: 11, DIR: 13}\n    encoder: {type: quadrature, A: 3}\n");
    EXPECT_TRUE(contains(m, "key 'wheels.left.encoder.B': missing")) << m;
    // A missing wheel, the old format, an unknown board, malformed YAML.
    EXPECT_TRUE(contains(load_error(head), "key 'wheels.left': missing"));
    EXPECT_TRUE(contains(load_error(head + "  left:\n    encoder: {type: single, OUT: 3}\n"), "key 'wheels.left.motor': missing"));
    EXPECT_TRUE(contains(load_error("board:\n  motor1: {enable_pin: 9}\n"), "old wiring format"));
    EXPECT_TRUE(contains(load_error("board: mega\n" + head), "unknown board 'mega'"));
    EXPECT_TRUE(contains(load_error("wheels: [1, 2\n"), "malformed YAML"));
    EXPECT_TRUE(contains(load_error("wheels: {}\nrobot: 1\n"), "b.yaml:2: key 'robot': unknown key"));
}

}  // namespace
}  // namespace ddmr::test
