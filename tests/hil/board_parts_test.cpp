// The board file's `parts:` list (hil/board.cpp, hil/parts/part_entries.cpp):
// its form, the wheels' inputs fed by parts, and every refusal, one line
// with FILE:LINE and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "hil/board.hpp"
#include "support/board_file.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

/// A shield's 74HC595 feeding two L293D halves (firmware/examples/afmotor_shield_v1).
const std::string kShieldParts =
    "board: uno\n"                                                        // 1
    "parts:\n"                                                            // 2
    "  - name: shield\n"                                                  // 3
    "    type: 74hc595\n"                                                 // 4
    "    DS: 8\n"                                                         // 5
    "    SHCP: 4\n"                                                       // 6
    "    STCP: 12\n"                                                      // 7
    "    OE: 7\n";                                                        // 8
const std::string kWheels =
    "wheels:\n"
    "  right: {motor: {driver: l293d, EN: 11, IN1: shield.Q2, IN2: shield.Q3}, encoder: {type: single, OUT: A0}}\n"
    "  left:  {motor: {driver: l293d, EN: 3, IN1: shield.Q1, IN2: shield.Q4}, encoder: {type: single, OUT: A1}}\n";

std::string load_error(const std::string& yaml) { return board_load_error(yaml); }

TEST(BoardParts, TheShieldsPartsAndItsWheelsFedByThem) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << kShieldParts + kWheels;
    const hil::BoardWiring b = hil::load_board_file(dir / "b.yaml");
    ASSERT_EQ(b.parts.size(), 1U);
    const hil::PartEntry& sr = b.parts[0];
    EXPECT_EQ(sr.name, "shield");
    EXPECT_EQ(sr.type, "74hc595");
    EXPECT_EQ(sr.line, 3);  // the entry starts at its first key, "- name: shield"
    EXPECT_EQ(sr.values.at("DS").pin, 8);
    EXPECT_EQ(sr.values.at("DS").line, 5);
    EXPECT_EQ(sr.values.at("MR").text, "high");  // left out: its default
    const hil::InputWire& in1 = b.wheel[0].motor[hil::DriverRole::in1];
    EXPECT_EQ(in1.part_output, "shield.Q2");
    EXPECT_FALSE(in1.on_pin());
    EXPECT_EQ(b.wheel[0].motor.driver, plant::DriverType::l293d);
    EXPECT_EQ(hil::wired_pins(b), (std::vector<int>{3, 4, 7, 8, 11, 12, 14, 15}));
}

struct Refusal {
    const char* what;
    std::string yaml;
    const char* message;
};

TEST(BoardParts, EachMistakeIsRefusedWithFileLineAndKey) {
    const std::string wheels_on_pins =
        "wheels:\n"
        "  right: {motor: {driver: l293d, EN: 11, IN1: A2, IN2: A3}, encoder: {type: single, OUT: A0}}\n"
        "  left:  {motor: {driver: l293d, EN: 3, IN1: A4, IN2: A5}, encoder: {type: single, OUT: A1}}\n";
    const std::vector<Refusal> cases = {
        {"unknown type", "parts:\n  - {name: x, type: 74hc596, DS: 8}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.type': unknown part type '74hc596' (known: 74hc595"},
        {"unknown key", "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4, STCP: 12, CLK: 5}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.CLK'"},
        {"missing key", "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.STCP': missing"},
        {"missing name", "parts:\n  - {type: 74hc595, DS: 8, SHCP: 4, STCP: 12}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts[0].name': missing"},
        {"two parts of one name",
         "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4, STCP: 12}\n"
         "  - {name: x, type: 74hc595, DS: 9, SHCP: 4, STCP: 12}\n" + wheels_on_pins,
         "b.yaml:3: key 'parts.x.name': a second part called 'x'"},
        {"pin used twice (a part's input on a wheel's pin)",
         "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4, STCP: A2}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.STCP': pin 16 is already used by wheels.right.motor.IN1"},
        {"not a pin", "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4, STCP: 99}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.STCP': '99' is not a pin"},
        {"a wheel fed by no part", kShieldParts + "wheels:\n"
         "  right: {motor: {driver: l293d, EN: 11, IN1: shed.Q2, IN2: shield.Q3}, encoder: {type: single, OUT: A0}}\n"
         "  left:  {motor: {driver: l293d, EN: 3, IN1: shield.Q1, IN2: shield.Q4}, encoder: {type: single, OUT: A1}}\n",
         "b.yaml:10: key 'wheels.right.motor.IN1': 'shed.Q2': no part is called 'shed': the input is fed by nothing"},
        {"a wheel fed by no port", kShieldParts + "wheels:\n"
         "  right: {motor: {driver: l293d, EN: 11, IN1: shield.Q8, IN2: shield.Q3}, encoder: {type: single, OUT: A0}}\n"
         "  left:  {motor: {driver: l293d, EN: 3, IN1: shield.Q1, IN2: shield.Q4}, encoder: {type: single, OUT: A1}}\n",
         "b.yaml:10: key 'wheels.right.motor.IN1': 'shield.Q8': part 'shield' (74hc595) has no output 'Q8'"},
        {"a part fed by nothing", "parts:\n  - {name: x, type: 74hc595, DS: y.Q7S, SHCP: 4, STCP: 12}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.x.DS': 'y.Q7S': no part is called 'y': the input is fed by nothing"},
        {"a loop of parts",
         "parts:\n  - {name: a, type: 74hc595, DS: b.Q7S, SHCP: 4, STCP: 12}\n"
         "  - {name: b, type: 74hc595, DS: a.Q7S, SHCP: 4, STCP: 12}\n" + wheels_on_pins,
         "b.yaml:2: key 'parts.a': a loop of parts feeding each other"},
        {"a PWM input fed by a part",
         "parts:\n  - {name: x, type: 74hc595, DS: 8, SHCP: 4, STCP: 12}\n"
         "wheels:\n"
         "  right: {motor: {driver: dir-pwm, PWM: x.Q0, DIR: 13}, encoder: {type: single, OUT: 2}}\n"
         "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 9}, encoder: {type: single, OUT: 3}}\n",
         "b.yaml:4: key 'wheels.right.motor.PWM': the L298 shield input PWM needs a timer's PWM"},
        {"parts not a list", "parts: {name: x}\n" + wheels_on_pins, "b.yaml:1: key 'parts': expected a list of parts"},
    };
    for (const Refusal& c : cases) {
        const std::string m = load_error(c.yaml);
        EXPECT_NE(m.find(c.message), std::string::npos) << c.what << ": got \"" << m << "\"";
        EXPECT_EQ(m.find('\n'), std::string::npos) << c.what << ": not one line";
    }
}

// Drivers and encoders are part types too: a parts: entry with `wheel:` is the
// same wiring as the wheels: shorthand.
TEST(BoardParts, DriversAndEncodersAsPartsAreTheWheelsShorthand) {
    const std::string as_parts = kShieldParts +
        "  - {name: m1, type: l293d, wheel: right, EN: 11, IN1: shield.Q2, IN2: shield.Q3}\n"   // 9
        "  - {name: m2, type: l293d, wheel: left, EN: 3, IN1: shield.Q1, IN2: shield.Q4}\n"     // 10
        "  - {name: e1, type: single, wheel: right, OUT: A0}\n"                                  // 11
        "  - {name: e2, type: quadrature, wheel: left, A: A1, B: A2, reversed: true}\n";         // 12
    TempDir dir;
    std::ofstream(dir / "parts.yaml") << as_parts;
    std::ofstream(dir / "wheels.yaml") << kShieldParts + kWheels;
    const hil::BoardWiring p = hil::load_board_file(dir / "parts.yaml");
    const hil::BoardWiring w = hil::load_board_file(dir / "wheels.yaml");
    ASSERT_EQ(p.parts.size(), 1U);  // the wheel parts are on the wheels
    for (std::size_t m = 0; m < 2; ++m) {
        EXPECT_EQ(p.wheel[m].motor.driver, w.wheel[m].motor.driver);
        for (std::size_t r = 0; r < hil::kDriverRoleCount; ++r) {
            EXPECT_EQ(p.wheel[m].motor.input[r].pin, w.wheel[m].motor.input[r].pin);
            EXPECT_EQ(p.wheel[m].motor.input[r].part_output, w.wheel[m].motor.input[r].part_output);
        }
    }
    EXPECT_EQ(p.wheel[0].encoder.kind, hil::EncoderKind::single);
    EXPECT_EQ(p.wheel[1].encoder.kind, hil::EncoderKind::quadrature);
    EXPECT_EQ(p.wheel[1].encoder.pin, (std::array<int, 2>{15, 16}));
    EXPECT_TRUE(p.wheel[1].encoder.reversed);
    // Mistakes name the part's key.
    const std::string clash = kShieldParts +
        "  - {name: m1, type: l293d, wheel: right, EN: 11, IN1: shield.Q2, IN2: 8}\n"
        "  - {name: m2, type: l293d, wheel: left, EN: 3, IN1: shield.Q1, IN2: shield.Q4}\n";
    EXPECT_NE(load_error(clash).find("b.yaml:5: key 'parts.shield.DS': pin 8 is already used by parts.m1.IN2"),
              std::string::npos) << load_error(clash);
    const std::string twice = as_parts + kWheels;
    EXPECT_NE(load_error(twice).find("key 'wheels.right.motor': given twice: parts.m1 is this wheel's motor driver"),
              std::string::npos) << load_error(twice);
    const std::string two_drivers = as_parts + "  - {name: m3, type: l298n, wheel: left, EN: 5, IN1: 6, IN2: 9}\n";
    EXPECT_NE(load_error(two_drivers).find("b.yaml:13: key 'parts.m3.wheel': the left wheel's motor driver is given "
                                           "twice (also parts.m2)"),
              std::string::npos) << load_error(two_drivers);
    const std::string no_wheel = kShieldParts + "  - {name: m1, type: l293d, EN: 11, IN1: shield.Q2, IN2: shield.Q3}\n";
    EXPECT_NE(load_error(no_wheel).find("key 'parts.m1.wheel': missing"), std::string::npos) << load_error(no_wheel);
}

TEST(BoardParts, TwoPartsMayShareAnInputPin) {
    // Two 74HC595s on one clock and one latch, the second fed by the first's Q7S.
    const std::string yaml =
        "parts:\n"
        "  - {name: a, type: 74hc595, DS: 8, SHCP: 4, STCP: 12}\n"
        "  - {name: b, type: 74hc595, DS: a.Q7S, SHCP: 4, STCP: 12}\n"
        "wheels:\n"
        "  right: {motor: {driver: l293d, EN: 11, IN1: a.Q0, IN2: b.Q0}, encoder: {type: single, OUT: A0}}\n"
        "  left:  {motor: {driver: l293d, EN: 3, IN1: a.Q1, IN2: b.Q1}, encoder: {type: single, OUT: A1}}\n";
    EXPECT_EQ(load_error(yaml), "");
}

}  // namespace
}  // namespace ddmr::test
