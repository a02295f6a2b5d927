// Tests for tools/scenario/scenario_yaml: the scenario format is checked
// before anything runs; every refusal names file, line and key.
#include "scenario/scenario_yaml.hpp"

#include <gtest/gtest.h>

#include <string>

#include "support/test_paths.hpp"

namespace ddmr::tools::scenario {
namespace {

const std::filesystem::path kFile = "/tmp/suite/case.yaml";

LoadOptions options() {
    LoadOptions o;
    o.reference_firmware = test::firmware_elf();
    return o;
}

Scenario parse(const std::string& text) { return parse_scenario(text, kFile, options()); }

/// The message of the ScenarioError `text` raises ("" if none).
std::string refusal(const std::string& text) {
    try {
        parse(text);
    } catch (const ScenarioError& e) {
        return e.what();
    }
    return "";
}

TEST(ScenarioDuration, UnitsAndRounding) {
    EXPECT_EQ(parse_duration("500ms", 16'000'000), 8'000'000U);
    EXPECT_EQ(parse_duration("1.5 s", 16'000'000), 24'000'000U);
    EXPECT_EQ(parse_duration("250us", 16'000'000), 4'000U);
    EXPECT_EQ(parse_duration("1000 cycles", 16'000'000), 1'000U);
    EXPECT_EQ(parse_duration("0.03125us", 16'000'000), 1U);  // half a cycle rounds up
    EXPECT_EQ(parse_duration("0s", 16'000'000), 0U);
    for (const char* bad : {"500", "-1s", "1 min", "nan s", "s", "1e400 s", ""}) {
        EXPECT_THROW(parse_duration(bad, 16'000'000), std::invalid_argument) << bad;
    }
}

TEST(ScenarioYaml, ParsesStepsWithTheirLinesAndDefaults) {
    const Scenario s = parse(R"(name: demo
timeout: 30s
serial: { baud: 19200 }
steps:
  - delay: 100ms
  - write-serial: "1"
  - wait-serial: "END"
  - expect-var: { name: Count1, type: int32, op: ">=", value: 7000 }
  - expect-loop: { max_us: [900, 1300] }
  - stall: { motor: 2, for: 300ms }
)");
    EXPECT_EQ(s.name, "demo");
    EXPECT_EQ(s.baud, 19200U);
    EXPECT_EQ(s.timeout, 480'000'000U);
    EXPECT_EQ(s.firmware, test::firmware_elf());
    ASSERT_EQ(s.steps.size(), 6U);
    EXPECT_EQ(s.steps[0].line, 5);
    EXPECT_EQ(std::get<Delay>(s.steps[0].action).duration, 1'600'000U);
    EXPECT_EQ(std::get<WaitSerial>(s.steps[2].action).timeout, 0U);  // none: the scenario's timeout ends it
    const auto& v = std::get<ExpectVar>(s.steps[3].action);
    EXPECT_EQ(v.op, CompareOp::kGe);
    EXPECT_EQ(v.type, hil::VarType::kInt32);
    const auto& l = std::get<ExpectLoop>(s.steps[4].action);
    EXPECT_EQ(l.max_us.min, 900.0);
    EXPECT_EQ(l.max_us.max, 1300.0);
    EXPECT_TRUE(s.needs_loop_profile());
    EXPECT_EQ(std::get<Stall>(s.steps[5].action).duration, 4'800'000U);
    EXPECT_EQ(s.steps[5].line, 10);
}

TEST(ScenarioYaml, TheSeedReachesTheEncoders) {
    const Scenario s = parse("timeout: 1s\nseed: 42\nsteps:\n  - delay: 1ms\n");
    EXPECT_EQ(s.plant.encoder[0].seed, 42U);
    EXPECT_EQ(s.plant.encoder[1].seed, 43U);
}

TEST(ScenarioYaml, PlantOverridesApply) {
    const Scenario s =
        parse("timeout: 1s\nplant: { overrides: { motor1: { resistance_ohm: 6.5 } } }\nsteps:\n  - delay: 1ms\n");
    EXPECT_EQ(s.plant.motor[0].resistance_ohm, 6.5);
    EXPECT_EQ(s.plant.motor[1].resistance_ohm, plant::default_robot_params().motor[1].resistance_ohm);
}

TEST(ScenarioYaml, RefusesWithFileLineAndKey) {
    struct Case {
        const char* text;
        const char* expected;
    };
    const Case cases[] = {
        {"timeout: 1s\nsteps:\n  - delay: 1ms\nfirmwre: x.elf\n", "case.yaml:4: key '(top).firmwre': unknown key"},
        {"timeout: 1s\nsteps:\n  - dance: 1ms\n", "case.yaml:3: key 'dance': unknown step"},
        {"timeout: 1s\nsteps:\n  - delay: 100\n", "case.yaml:3: key 'delay': duration '100'"},
        {"timeout: 1s\nsteps:\n  - expect-pwm: { pin: 4, duty: 0.5 }\n", "key 'expect-pwm.pin': pin 4 has no timer output"},
        {"timeout: 1s\nsteps:\n  - expect-warning: \"(\"\n", "expect-warning"},
        {"board: no_such_board.yaml\ntimeout: 1s\nsteps:\n  - delay: 1ms\n", "key 'board'"},
        {"timeout: 1s\nsteps:\n  - expect-pwm: { pin: 10, duty: .nan }\n", "key 'expect-pwm.duty'"},
        {"timeout: 1s\nsteps:\n  - expect-pin: { pin: 20, value: 1 }\n", "key 'expect-pin.pin': 20"},
        {"timeout: 1s\nsteps:\n  - expect-pin: { pin: 2, value: 1, colour: red }\n", "key 'expect-pin.colour': unknown key"},
        {"timeout: 1s\nsteps:\n  - expect-serial: \"([\"\n", "not a valid regular expression"},
        {"timeout: 1s\nsteps:\n  - inject: { encoder: 3, drop: 0.05 }\n", "key 'inject.encoder'"},
        {"timeout: 1s\nsteps:\n  - battery: { volts: -5 }\n", "key 'battery.volts'"},
        {"timeout: 1s\nsteps:\n  - expect-eeprom: { bin: ../../etc/passwd }\n", "leaves the scenario's folder"},
        {"timeout: 1s\nsteps:\n  - expect-eeprom: { bin: /etc/passwd }\n", "is absolute"},
        {"timeout: 1s\nsteps: []\n", "key 'steps': expected a non-empty list"},
        {"steps:\n  - delay: 1ms\n", "missing required key 'timeout'"},
        {"timeout: 0s\nsteps:\n  - delay: 1ms\n", "key 'timeout': must be longer than 0"},
        {"timeout: 1s\nsteps:\n  - delay: 1ms\n    write-serial: x\n", "each step is a mapping with one key"},
        {"timeout: 1s\nplant: { overrides: { motor1: { resistance_ohm: -1 } } }\nsteps:\n  - delay: 1ms\n",
         "resistance_ohm"},
        {"timeout: 1s\nserial: { baud: 0 }\nsteps:\n  - delay: 1ms\n", "key 'serial.baud'"},
        {"timeout: [1s\n", "malformed YAML"},
        {"timeout: 1s\nfirmware: { elf: a.elf, sketch: b/b.ino }\nsteps:\n  - delay: 1ms\n", "give one of elf"},
        {"timeout: 1s\nfirmware: { sketch: ../x/x.ino }\nsteps:\n  - delay: 1ms\n", "leaves the scenario's folder"},
        {"timeout: 1s\nfirmware: { hex: a.hex }\nsteps:\n  - delay: 1ms\n", "key 'firmware.hex': unknown key"},
    };
    for (const Case& c : cases) {
        const std::string msg = refusal(c.text);
        EXPECT_NE(msg.find(c.expected), std::string::npos) << c.text << "\n got: " << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(ScenarioYaml, TheCommandLineFirmwareWins) {
    LoadOptions o = options();
    o.firmware_override = "/some/where/else.elf";
    const Scenario s = parse_scenario("timeout: 1s\nfirmware: reference\nsteps:\n  - delay: 1ms\n", kFile, o);
    EXPECT_EQ(s.firmware, "/some/where/else.elf");
}

TEST(ScenarioYaml, EveryShippedScenarioLoads) {
    int n = 0;
    for (const auto& e : std::filesystem::directory_iterator(test::source_dir() / "tests/scenarios")) {
        if (e.path().extension() != ".yaml") continue;
        EXPECT_NO_THROW(load_scenario(e.path(), options())) << e.path();
        ++n;
    }
    EXPECT_GE(n, 6);
}

}  // namespace
}  // namespace ddmr::tools::scenario
