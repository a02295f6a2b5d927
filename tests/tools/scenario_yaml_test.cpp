// Tests for tools/scenario/scenario_yaml: the scenario format is checked
// before anything runs; every refusal names file, line and key.
#include "scenario/scenario_yaml.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/truth_csv.hpp"
#include "hil/plant_coupler.hpp"
#include "support/temp_dir.hpp"
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

TEST(ScenarioYaml, ParsesPlantSignalStepsAndWheelNames) {
    const Scenario s = parse(R"(timeout: 10s
steps:
  - wait-until: { signal: x_m, op: ">=", value: 0.05, timeout: 7s }
  - wait-until: { signal: left.edges, value: 3 }
  - expect: { signal: left.wheel_rad_s, between: [1.5, 30] }
  - expect: { signal: vbatt_V, op: "<", value: 12 }
  - expect: { signal: dir2, value: 1 }
  - inject: { encoder: left, drop: 0.1 }
  - stall: { motor: right, for: 10ms }
  - slip: { wheel: left, traction: 0.5 }
  - slip: { wheel: 1, traction: 0.5 }
)");
    ASSERT_EQ(s.steps.size(), 9U);
    const auto& w = std::get<WaitUntil>(s.steps[0].action);
    EXPECT_EQ(w.signal, "x_m");
    EXPECT_EQ(w.op, CompareOp::kGe);
    EXPECT_EQ(w.value, 0.05);
    EXPECT_EQ(w.timeout, 112'000'000U);
    EXPECT_EQ(s.steps[0].kind, "wait-until");
    EXPECT_EQ(s.steps[0].line, 3);
    const auto& w2 = std::get<WaitUntil>(s.steps[1].action);
    EXPECT_EQ(w2.op, CompareOp::kEq);  // as expect-var: == by default
    EXPECT_EQ(w2.timeout, 0U);         // none: the scenario's timeout ends it
    const auto& b = std::get<ExpectSignal>(s.steps[2].action);
    EXPECT_EQ(b.signal, "left.wheel_rad_s");
    ASSERT_TRUE(b.between.set());
    EXPECT_EQ(*b.between.min, 1.5);
    EXPECT_EQ(*b.between.max, 30.0);
    const auto& o = std::get<ExpectSignal>(s.steps[3].action);
    EXPECT_FALSE(o.between.set());
    EXPECT_EQ(o.op, CompareOp::kLt);
    EXPECT_EQ(o.value, 12.0);
    EXPECT_EQ(std::get<ExpectSignal>(s.steps[4].action).op, CompareOp::kEq);
    // right = 1 = motor 1, left = 2 = motor 2; numbers still work.
    EXPECT_EQ(std::get<InjectDrop>(s.steps[5].action).encoder, 2);
    EXPECT_EQ(std::get<Stall>(s.steps[6].action).motor, 1);
    EXPECT_EQ(std::get<Slip>(s.steps[7].action).wheel, 2);
    EXPECT_EQ(std::get<Slip>(s.steps[8].action).wheel, 1);
}

TEST(ScenarioYaml, PlantSignalsReadTheTruthColumns) {
    hil::TruthSample t;
    t.x_m = 0.25;
    t.ia1_A = 0.5;
    t.ia2_A = 0.75;
    t.wheel1_rad_s = 3.0;
    t.wheel2_rad_s = 4.0;
    t.edges1 = 10;
    t.edges2 = 20;
    t.duty1 = 0.1;
    t.duty2 = 0.2;
    t.dir2 = true;
    EXPECT_EQ(plant_signal(t, "x_m"), 0.25);
    EXPECT_EQ(plant_signal(t, "right.wheel_rad_s"), 3.0);
    EXPECT_EQ(plant_signal(t, "left.wheel_rad_s"), 4.0);
    EXPECT_EQ(plant_signal(t, "right.current_A"), 0.5);
    EXPECT_EQ(plant_signal(t, "left.current_A"), 0.75);
    EXPECT_EQ(plant_signal(t, "right.edges"), 10.0);
    EXPECT_EQ(plant_signal(t, "left.edges"), 20.0);
    EXPECT_EQ(plant_signal(t, "right.duty"), 0.1);
    EXPECT_EQ(plant_signal(t, "left.duty"), 0.2);
    EXPECT_EQ(plant_signal(t, "dir1"), 0.0);
    EXPECT_EQ(plant_signal(t, "dir2"), 1.0);
    EXPECT_THROW(plant_signal(t, "t_s"), std::invalid_argument);
    // Every truth.csv column but t_s is a signal.
    std::string header = truth_csv_header(/*with_drive=*/true);
    header.pop_back();  // "\n"
    std::size_t columns = 0;
    for (std::size_t at = 0; at <= header.size();) {
        const std::size_t comma = std::min(header.find(',', at), header.size());
        const std::string column = header.substr(at, comma - at);
        if (column != "t_s") {
            EXPECT_TRUE(is_plant_signal(column)) << column;
            ++columns;
        }
        at = comma + 1;
    }
    EXPECT_EQ(columns, 16U);
    EXPECT_EQ(plant_signal_names().size(), 24U);
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
        {"timeout: 1s\nsteps:\n  - expect-pwm: { pin: 9, duty: 0.5 }\n",
         "case.yaml:3: key 'expect-pwm.pin': pin 9 feeds no motor driver input of the board (built-in default board); "
         "the driver inputs on timer pins are 10, 11"},
        {"timeout: 1s\nsteps:\n  - expect-isr: { vector: BOGUS }\n",
         "case.yaml:3: key 'expect-isr.vector': 'BOGUS' is not an interrupt of the ATmega328P (avr-libc's names "
         "without _vect: INT0, INT1, PCINT0,"},
        {"timeout: 1s\nsteps:\n  - expect-isr: { vector: USART0_RX }\n", "'USART0_RX' is not an interrupt of the ATmega328P"},
        {"timeout: 1s\nsteps:\n  - expect-pin: { pin: D22, value: 1 }\n",
         "key 'expect-pin.pin': 'D22' is not a pin of the Arduino Uno"},
        {"timeout: 1s\nserial: { port: Serial1 }\nsteps:\n  - delay: 1ms\n",
         "case.yaml:2: key 'serial.port': 'Serial1' is not a serial port of the Arduino Uno (ATmega328P): Serial"},
        {"timeout: [1s\n", "malformed YAML"},
        {"timeout: 1s\nfirmware: { elf: a.elf, sketch: b/b.ino }\nsteps:\n  - delay: 1ms\n", "give one of elf"},
        {"timeout: 1s\nfirmware: { sketch: ../x/x.ino }\nsteps:\n  - delay: 1ms\n", "leaves the scenario's folder"},
        {"timeout: 1s\nfirmware: { hex: a.hex }\nsteps:\n  - delay: 1ms\n", "key 'firmware.hex': unknown key"},
        // wait-until and expect on plant signals
        {"timeout: 1s\nsteps:\n  - delay: 1ms\n  - wait-until: { signal: x, op: \">\", value: 1 }\n",
         "case.yaml:4: key 'wait-until.signal': 'x' is not a signal (one of x_m, "},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: t_s, value: 1 }\n", "key 'wait-until.signal': 't_s'"},
        {"timeout: 1s\nsteps:\n  - wait-until: { op: \">\", value: 1 }\n",
         "case.yaml:3: key 'wait-until': missing required key 'signal'"},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: x_m, op: \">\" }\n",
         "case.yaml:3: key 'wait-until': missing required key 'value'"},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: x_m, op: \"=>\", value: 1 }\n",
         "key 'wait-until.op': '=>' is not one of =="},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: x_m, value: 1, timeout: 5 }\n",
         "key 'wait-until.timeout': duration '5'"},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: x_m, value: 1, between: [0, 1] }\n",
         "key 'wait-until.between': unknown key"},
        {"timeout: 1s\nsteps:\n  - wait-until: { signal: x_m, value: .nan }\n", "key 'wait-until.value'"},
        {"timeout: 1s\nsteps:\n  - wait-until: x_m\n", "key 'wait-until': expected a mapping of keys"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: left.speed, value: 1 }\n",
         "case.yaml:3: key 'expect.signal': 'left.speed' is not a signal (one of"},
        {"timeout: 1s\nsteps:\n  - expect: { value: 1 }\n", "case.yaml:3: key 'expect': missing required key 'signal'"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, op: \"<\" }\n",
         "case.yaml:3: key 'expect': missing required key 'value' (or give between: [min, max])"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m }\n", "key 'expect': missing required key 'value'"},
        {"timeout: 1s\nsteps:\n  - expect:\n      signal: x_m\n      between: [2, 1]\n",
         "case.yaml:5: key 'expect.between': min 2 is above max 1"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, op: \"<\", between: [0, 1] }\n",
         "case.yaml:3: key 'expect': give op and value, or between: [min, max], not both"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, value: 1, between: [0, 1] }\n", "not both"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, between: [0, 1, 2] }\n",
         "key 'expect.between': expected [min, max]"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, between: 1 }\n", "key 'expect.between': expected [min, max]"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, between: [a, 1] }\n",
         "key 'expect.between[0]': 'a' is not a number"},
        {"timeout: 1s\nsteps:\n  - expect: { signal: x_m, value: 1, tol: 0.1 }\n", "key 'expect.tol': unknown key"},
        // wheel names in faults
        {"timeout: 1s\nsteps:\n  - delay: 1ms\n  - stall: { motor: front, for: 1ms }\n",
         "case.yaml:4: key 'stall.motor': 'front' is not a wheel (1 or right, 2 or left)"},
        {"timeout: 1s\nsteps:\n  - slip: { wheel: Left, traction: 0.5 }\n", "key 'slip.wheel': 'Left' is not a wheel"},
        {"timeout: 1s\nsteps:\n  - inject: { encoder: centre, drop: 0.1 }\n", "key 'inject.encoder': 'centre' is not a wheel"},
        {"timeout: 1s\nsteps:\n  - slip: { wheel: 0, traction: 0.5 }\n", "key 'slip.wheel': '0' is not a wheel"},
    };
    for (const Case& c : cases) {
        const std::string msg = refusal(c.text);
        EXPECT_NE(msg.find(c.expected), std::string::npos) << c.text << "\n got: " << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(ScenarioYaml, BareStepsAndTornReadVariableLists) {
    const Scenario s =
        parse("timeout: 1s\nsteps:\n  - reset\n  - expect-no-torn-reads\n  - expect-no-torn-reads: [Count1, Count2]\n");
    ASSERT_EQ(s.steps.size(), 3U);
    EXPECT_TRUE(std::holds_alternative<Reset>(s.steps[0].action));
    EXPECT_EQ(s.steps[1].line, 4);
    EXPECT_TRUE(std::get<ExpectNoTornReads>(s.steps[1].action).variables.empty());
    EXPECT_EQ(std::get<ExpectNoTornReads>(s.steps[2].action).variables, (std::vector<std::string>{"Count1", "Count2"}));
    EXPECT_NE(refusal("timeout: 1s\nsteps:\n  - delay\n").find("case.yaml:3: key 'steps[]': each step is a mapping"),
              std::string::npos);
    EXPECT_NE(refusal("timeout: 1s\nsteps:\n  - expect-no-torn-reads: []\n").find("a list of variable names"),
              std::string::npos);
    EXPECT_NE(refusal("timeout: 1s\nsteps:\n  - expect-no-torn-reads: 3\n").find("takes no value"), std::string::npos);
}

TEST(ScenarioYaml, TheCommandLineFirmwareWins) {
    LoadOptions o = options();
    o.firmware_override = "/some/where/else.elf";
    const Scenario s = parse_scenario("timeout: 1s\nfirmware: reference\nsteps:\n  - delay: 1ms\n", kFile, o);
    EXPECT_EQ(s.firmware, "/some/where/else.elf");
}

TEST(ScenarioYaml, DurationsAndPinsAreTheBoards) {
    // The Pro Mini example's scenario: the board file comes first, so its
    // 8 MHz clock turns every duration into cycles (500 ms = 4,000,000).
    const auto file = test::source_dir() / "firmware/examples/pro_mini_8mhz_tb6612/scenario.yaml";
    const Scenario s = load_scenario(file, options());
    EXPECT_EQ(s.board.model, hil::BoardModel::pro_mini_8mhz);
    EXPECT_EQ(s.timeout, 4u * 8'000'000u);  // timeout: 4s
    const auto* d = std::get_if<Delay>(&s.steps.at(2).action);
    ASSERT_NE(d, nullptr);
    EXPECT_EQ(d->duration, 750u * 8'000u);  // delay: 750ms
    // On the Uno (no board file) the same text is 16 MHz cycles.
    EXPECT_EQ(parse("timeout: 4s\nsteps:\n  - delay: 750ms\n").timeout, 4u * 16'000'000u);
    // Pins are the board's: 20 digital pins, PWM where a timer output is.
    const std::string m = refusal("timeout: 1s\nsteps:\n  - expect-pwm: { pin: 4, duty: 0.5, tol: 0.1 }\n");
    EXPECT_NE(m.find("PWM pins: 3, 5, 6, 9, 10 and 11"), std::string::npos) << m;
    EXPECT_NE(refusal("timeout: 1s\nsteps:\n  - expect-pin: { pin: 20, value: 1 }\n").find("[0, 19]"),
              std::string::npos);
}

TEST(ScenarioYaml, TheSerialPortIsOneOfTheBoardsUsarts) {
    // A Mega robot with a Bluetooth module on Serial1: the adapter goes to USART1.
    namespace fs = std::filesystem;
    test::TempDir dir;
    fs::copy_file(test::source_dir() / "firmware/examples/mega_l298n_int45/board.yaml", dir / "board.yaml");
    const auto write = [&](const std::string& serial) {
        std::ofstream(dir / "s.yaml") << "board: board.yaml\ntimeout: 1s\nserial: " << serial
                                      << "\nsteps:\n  - delay: 1ms\n";
        return dir / "s.yaml";
    };
    EXPECT_EQ(load_scenario(write("{ baud: 9600 }"), options()).serial_usart, 0);
    EXPECT_EQ(load_scenario(write("{ port: Serial1 }"), options()).serial_usart, 1);
    EXPECT_EQ(load_scenario(write("{ port: Serial3 }"), options()).serial_usart, 3);
    try {
        load_scenario(write("{ port: Serial4 }"), options());
        FAIL() << "Serial4 accepted";
    } catch (const std::exception& e) {
        EXPECT_NE(std::string(e.what()).find("Serial, Serial1, Serial2 or Serial3"), std::string::npos) << e.what();
    }
}

TEST(ScenarioYaml, AWorldFileIsReadBesideTheScenarioAndItsMistakesNameIt) {
    namespace fs = std::filesystem;
    test::TempDir dir;
    std::ofstream(dir / "w.yaml") << "start: {x_m: 0.2}\nlines:\n  - {points_m: [[0, 0], [1, 0]]}\n";
    std::ofstream(dir / "s.yaml") << "world: w.yaml\ntimeout: 1s\nsteps:\n  - delay: 1ms\n";
    const Scenario s = load_scenario(dir / "s.yaml", options());
    ASSERT_TRUE(s.world_file);
    EXPECT_EQ(*s.world_file, dir / "w.yaml");
    ASSERT_TRUE(s.world.start);
    EXPECT_EQ(s.world.start->x_m, 0.2);
    EXPECT_EQ(s.world.lines.size(), 1U);
    std::ofstream(dir / "w.yaml") << "walls:\n  - {from_m: [0, 0], to_m: [0, 0]}\n";
    try {
        load_scenario(dir / "s.yaml", options());
        FAIL() << "a wall of zero length accepted";
    } catch (const std::exception& e) {
        EXPECT_EQ(std::string(e.what()),
                  (dir / "w.yaml").string() + ":2: key 'walls[0]': a wall of zero length (two corners at the same point)");
    }
    std::ofstream(dir / "s.yaml") << "world: nowhere.yaml\ntimeout: 1s\nsteps:\n  - delay: 1ms\n";
    EXPECT_THROW(load_scenario(dir / "s.yaml", options()), std::exception);
}

TEST(ScenarioYaml, PinsVectorsAndPwmPinsAreTheMegas) {
    namespace fs = std::filesystem;
    test::TempDir dir;
    fs::copy_file(test::source_dir() / "firmware/examples/mega_l298n_int45/board.yaml", dir / "board.yaml");
    std::ofstream(dir / "s.yaml") << "board: board.yaml\ntimeout: 1s\nsteps:\n"
                                     "  - expect-pin: { pin: D22, value: 1 }\n"
                                     "  - expect-pin: { pin: A8, value: 0 }\n"
                                     "  - expect-pin: { pin: 69, value: 0 }\n"
                                     "  - expect-pwm: { pin: D5, duty: 0.7 }\n"
                                     "  - expect-isr: { vector: USART1_RX }\n";
    const Scenario s = load_scenario(dir / "s.yaml", options());
    ASSERT_EQ(s.steps.size(), 5u);
    EXPECT_EQ(std::get<ExpectPin>(s.steps[0].action).pin, 22);
    EXPECT_EQ(std::get<ExpectPin>(s.steps[1].action).pin, 62);  // A8 = 54 + 8
    EXPECT_EQ(std::get<ExpectPin>(s.steps[2].action).pin, 69);
    EXPECT_EQ(std::get<ExpectPwm>(s.steps[3].action).pin, 5);
    EXPECT_EQ(std::get<ExpectIsr>(s.steps[4].action).vector, "USART1_RX");
    const auto refused = [&](const std::string& step) {
        std::ofstream(dir / "bad.yaml") << "board: board.yaml\ntimeout: 1s\nsteps:\n  - " << step << "\n";
        try {
            load_scenario(dir / "bad.yaml", options());
        } catch (const std::exception& e) {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    EXPECT_NE(refused("expect-pwm: { pin: 44, duty: 0.5 }").find("pin 44 feeds no motor driver input of the board"),
              std::string::npos);
    EXPECT_NE(refused("expect-isr: { vector: USART_RX }").find("'USART_RX' is not an interrupt of the ATmega2560"),
              std::string::npos);
    EXPECT_NE(refused("expect-pin: { pin: A16, value: 1 }").find("'A16' is not a pin of the Arduino Mega 2560"),
              std::string::npos);
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
