// The board file's `parts:` list (hil/board.cpp, hil/parts/part_entries.cpp):
// its form, the wheels' inputs fed by parts, and every refusal, one line
// with FILE:LINE and the key.
#include <gtest/gtest.h>

#include <fstream>

#include "hil/board.hpp"
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

std::string load_error(const std::string& yaml) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << yaml;
    try {
        (void)hil::load_board_file(dir / "b.yaml");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

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
