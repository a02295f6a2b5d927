// Every scenario step kind made to fail (issue 32, item 7): the checks that
// are otherwise seen only in runs that pass would not notice if they broke.
//
// A check (expect-*, wait-*) fails on its own. A step that acts (delay aside,
// it never fails: write-serial, fail-serial, inject, stall, battery, slip,
// push, reset) is made to fail a later check by what it does: each such case
// also runs a control, the same scenario without the action, which must
// pass. Every case asserts the verdict, the exit code, which step failed and
// its message word for word; a number the run measures is checked against
// bounds worked out by hand (the case's comment says how).
//
// Short runs: small fixture firmwares (tests/firmware) do in milliseconds
// what the reference sketch does only after its 5 s setup() delay:
//   echo_fixture.c       echoes the serial input upper-cased; drives no pin
//   drive_fixture.c      both motors at full drive from reset, INT0/INT1 of
//                        known length, interrupts off half the time
//   loop_fixture.c       a loop of 11 + 7 cycles, its mark named delay
//   race_fixture.c       a torn read of `ticks`
// All cases of a test run in one `ddmr-hil scenario` call, one worker each.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <optional>
#include <regex>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "scenario/step_catalog.hpp"
#include "support/scenario_cli.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const std::string kReference = "reference";
const std::string kEcho = "echo_fixture.elf";
const std::string kDrive = "drive_fixture.elf";
const std::string kLoop = "loop_fixture_delay.elf";
const std::string kRace = "race_fixture_racy.elf";

/// One step kind made to fail.
struct FailingCase {
    std::string kind;                ///< the step kind under test
    std::string name;                ///< the scenario's name (unique)
    std::string firmware;            ///< kReference, or a fixture ELF in test_firmware_dir()
    std::vector<std::string> steps;  ///< one step each, as after "  - "
    std::size_t under_test = 0;      ///< the index of the step of `kind`
    std::size_t failing = 0;         ///< the index of the step that fails (the last)
    std::string message;             ///< ECMAScript regex the failing step's whole message matches
    std::string timeout = "1s";
    std::string verdict = "fail";    ///< or "firmware" (exit 3)
    bool control = false;            ///< the scenario without steps[under_test] passes
    /// The message's first capture, a number, lies in [first, second].
    std::optional<std::pair<double, double>> measured;
    std::vector<std::pair<std::string, std::string>> files;  ///< name, bytes: beside the scenario
    std::function<void(const json& result)> also;            ///< a further check of result.json

    FailingCase& measuring(double lo, double hi) {
        measured = {lo, hi};
        return *this;
    }
    FailingCase& within(std::string t) {
        timeout = std::move(t);
        return *this;
    }
    FailingCase& as_error() {  ///< a firmware verdict (exit 3), not a failed check
        verdict = "firmware";
        return *this;
    }
    FailingCase& with_file(std::string file, std::string bytes) {
        files.emplace_back(std::move(file), std::move(bytes));
        return *this;
    }
    FailingCase& on_board(std::string yaml) {  ///< the scenario's `board:` (a file beside it)
        board = "board.yaml";
        return with_file("board.yaml", std::move(yaml));
    }
    /// The scenario's `world:`: a file beside it, named after the scenario
    /// (the cases of one run share their folder).
    FailingCase& in_world(std::string yaml) {
        world = name + "_world.yaml";
        return with_file(world, std::move(yaml));
    }
    std::string board;  ///< the scenario's board file, or the thesis robot
    std::string world;  ///< the scenario's world file, or none
};

/// The check `steps.back()` (of `kind`) fails with `message`.
FailingCase check(std::string kind, std::string name, std::string firmware, std::vector<std::string> steps,
                  std::string message) {
    FailingCase c;
    c.kind = std::move(kind);
    c.name = std::move(name);
    c.firmware = std::move(firmware);
    c.steps = std::move(steps);
    c.under_test = c.failing = c.steps.size() - 1;
    c.message = std::move(message);
    return c;
}

/// The action steps[action] (of `kind`) makes the check `steps.back()` fail
/// with `message`; without the action the scenario passes.
FailingCase action(std::string kind, std::size_t action, std::string name, std::string firmware,
                   std::vector<std::string> steps, std::string message) {
    FailingCase c = check(std::move(kind), std::move(name), std::move(firmware), std::move(steps), std::move(message));
    c.under_test = action;
    c.control = true;
    return c;
}

/// A step's kind: its text up to the colon ("reset" has none).
std::string kind_of(const std::string& step) { return step.substr(0, step.find(':')); }

/// The scenario file of `c` (without its action for the control). Step i is
/// on line kFirstStepLine + i.
constexpr int kFirstStepLine = 5;
std::string scenario_yaml(const FailingCase& c, bool control) {
    std::string y = "name: " + c.name + (control ? "_control" : "") + "\nfirmware: " + c.firmware +
                    "\ntimeout: " + c.timeout + "\nsteps:\n";
    for (std::size_t i = 0; i < c.steps.size(); ++i) {
        if (!control || i != c.under_test) y += "  - " + c.steps[i] + "\n";
    }
    if (!c.board.empty()) y += "board: " + c.board + "\n";  // after the steps: their lines stay
    if (!c.world.empty()) y += "world: " + c.world + "\n";
    return y;
}

void expect_case_failed(const FailingCase& c, const fs::path& out) {
    SCOPED_TRACE(c.kind + ", scenario " + c.name);
    const json j = result_of(out / c.name);
    EXPECT_EQ(j["verdict"], c.verdict);
    EXPECT_EQ(j["exit_code"], c.verdict == "fail" ? 1 : 3);
    // The failing step ends the scenario; every step before it passed.
    ASSERT_EQ(j["steps"].size(), c.failing + 1) << j.dump(1);
    for (std::size_t i = 0; i < c.failing; ++i) EXPECT_TRUE(j["steps"][i]["passed"].get<bool>()) << j["steps"][i];
    const json& step = j["steps"][c.failing];
    EXPECT_FALSE(step["passed"].get<bool>());
    const std::string failing_kind = kind_of(c.steps[c.failing]);
    EXPECT_EQ(step["kind"], failing_kind);
    const std::string where = c.name + ".yaml:" + std::to_string(kFirstStepLine + static_cast<int>(c.failing)) + ": " +
                              failing_kind + " failed at t=";
    const std::string message = step["message"].get<std::string>();
    const std::string whole = j["message"].get<std::string>();
    EXPECT_NE(whole.find(where), std::string::npos) << whole;
    EXPECT_EQ(whole.substr(whole.size() - std::min(whole.size(), message.size())), message);
    std::smatch m;
    ASSERT_TRUE(std::regex_match(message, m, std::regex(c.message))) << message << "\ndoes not match\n" << c.message;
    if (c.measured) {
        ASSERT_GE(m.size(), 2U) << c.message;
        const double v = std::stod(m[1].str());
        EXPECT_GE(v, c.measured->first) << message;
        EXPECT_LE(v, c.measured->second) << message;
    }
    if (c.control) {
        const json k = result_of(out / (c.name + "_control"));
        EXPECT_EQ(k["verdict"], "pass") << "without its " << c.kind << " step: " << k["message"];
    }
    if (c.also) c.also(j);
}

/// Runs every case (and control) in one `ddmr-hil scenario` call and checks each.
void expect_each_fails(const std::vector<FailingCase>& cases) {
    TempDir dir;
    std::string files;
    std::set<std::string> copied;
    for (const FailingCase& c : cases) {
        ASSERT_EQ(kind_of(c.steps.at(c.under_test)), c.kind) << c.name;
        if (c.firmware != kReference && copied.insert(c.firmware).second) {
            fs::copy_file(test_firmware_dir() / c.firmware, dir / c.firmware);
        }
        for (const auto& [name, bytes] : c.files) write_text(dir, name, bytes);
        files += " " + sh_quote(write_text(dir, c.name + ".yaml", scenario_yaml(c, false)).string());
        if (c.control) {
            files += " " + sh_quote(write_text(dir, c.name + "_control.yaml", scenario_yaml(c, true)).string());
        }
    }
    const ProcessResult r = scenario(files + " -j 2 --out " + sh_quote((dir / "out").string()));
    const bool any_error = std::any_of(cases.begin(), cases.end(), [](const auto& c) { return c.verdict == "firmware"; });
    EXPECT_EQ(r.exit_code, any_error ? 3 : 1) << r.out << r.err;
    for (const FailingCase& c : cases) expect_case_failed(c, dir / "out");
}

/// A world of one tape along the x axis, through the robot's start.
const std::string kTapeAlongX = "lines:\n  - {points_m: [[-1, 0], [3, 0]]}\n";
/// The thesis robot's wiring (drive_fixture's pins), for `parts:` after it.
const std::string kThesisBoardWith =
    "board: uno\n"
    "wheels:\n"
    "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n"
    "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 3}}\n";

// --- serial and pins ---------------------------------------------------------
std::vector<FailingCase> serial_and_pin_cases() {
    // 9600 baud: a byte is 10 bits, 1.04 ms. "hi\n" is in by 3.1 ms, and its
    // echo's '\n' (one byte behind) has arrived by 4.2 ms.
    const std::vector<std::string> echo_hi = {"fail-serial: \"^HI$\"", "write-serial: \"hi\\n\"", "delay: 20ms"};
    const std::string hi_matched = R"(fail-serial '\^HI\$' matched the line 'HI' at t=(0\.\d+) s)";
    return {
        check("delay", "delay_past_the_timeout", kEcho, {"delay: 100ms"},
              R"(timeout after 0\.05 simulated s \(the scenario's timeout\))")
            .within("50ms")
            .as_error(),
        action("write-serial", 1, "write_serial_is_echoed", kEcho, echo_hi, hi_matched).measuring(0.003, 0.0045),
        action("fail-serial", 0, "fail_serial_matches", kEcho, echo_hi, hi_matched).measuring(0.003, 0.0045),
        check("wait-serial", "wait_serial_for_other_text", kEcho,
              {"write-serial: \"abc\"", "wait-serial: {text: \"abd\", timeout: 50ms}"},
              R"(expected 'abd' within 0\.050 s; received 3 bytes \(0 framing errors\), ending 'ABC')"),
        check("expect-serial", "expect_serial_other_text", kEcho,
              {"write-serial: \"abc\"", "delay: 20ms", "expect-serial: \"abc\""},
              R"(expected the output to match /abc/; it does not: received 3 bytes \(0 framing errors\), ending 'ABC')"),
        // drive_fixture sets D10-D13 high at reset, and never changes them.
        check("wait-pin", "wait_pin_that_stays_high", kDrive,
              {"delay: 1ms", "wait-pin: {pin: 12, value: 0, timeout: 10ms}"},
              R"(expected pin 12 to become 0 within 0\.010 s; it stayed 1)"),
        check("expect-pin", "expect_pin_high", kDrive, {"delay: 1ms", "expect-pin: {pin: 13, value: 0}"},
              R"(expected pin 13 = 0, got 1)"),
        // A 74HC595 whose clocks drive_fixture never moves: its outputs stay low.
        check("expect-part", "expect_part_never_latched", kDrive, {"delay: 1ms", "expect-part: {part: sr, port: Q0, value: 1}"},
              R"(expected part sr's Q0 = 1, got 0)")
            .on_board("parts:\n  - {name: sr, type: 74hc595, DS: 4, SHCP: 5, STCP: 6}\nwheels:\n"
                      "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n"
                      "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 3}}\n"),
        // No timer drives D10: its static high level is duty 1.
        check("expect-pwm", "expect_pwm_of_a_static_high", kDrive,
              {"delay: 1ms", "expect-pwm: {pin: 10, duty: 0.5, tol: 0.1}"},
              R"(expected pin 10 duty 0\.5000 \+- 0\.1000, got 1\.0000)"),
        check("expect-warning", "expect_warning_none_given", kDrive, {"delay: 1ms", "expect-warning: \"never\""},
              R"(expected a wiring warning matching /never/; there are 0)"),
        // echo_fixture never makes the four driver inputs outputs, nor pulls them up.
        check("expect-warning", "expect_warning_other_text", kEcho, {"delay: 1ms", "expect-warning: \"pull-up\""},
              R"(expected a wiring warning matching /pull-up/; there are 4: pin 10 \(right .*\) is never set as an )"
              R"(output: the driver sees only a floating input \(read as low\))"),
    };
}

// --- firmware and robot checks --------------------------------------------------
std::vector<FailingCase> firmware_check_cases() {
    // Full speed: 1055 rad/s at the motor, 8 edges a turn: 1,344 edges/s, one
    // every 11,900 cycles; less while the motors spin up (69 ms time constant).
    return {
        // count1 = edges - lost; an off window (20,000 cycles) holds at most
        // two edges of a wheel, so at most every other edge is lost.
        check("expect-var", "expect_var_counted", kDrive,
              {"wait-until: {signal: right.edges, op: \">=\", value: 50, timeout: 200ms}",
               "expect-var: {name: count1, type: uint32, op: \"<\", value: 10}"},
              R"(expected count1 < 10, got (\d+))")
            .measuring(24, 52),
        // The robot starts at the origin, heading 0; echo_fixture drives nothing.
        check("expect-pose", "expect_pose_of_the_truth", kEcho,
              {"delay: 1ms", "expect-pose: {x_m: 0.1, y_m: 0, tol_m: 0.01}"},
              R"(expected the truth pose within 0\.01 m of \(0\.1000, 0\.0000\); got \(0\.0000, 0\.0000\) )"
              R"(theta 0\.0000 rad, 0\.1000 m away)"),
        // The reference's Ex, Ey, Theta are 0 until its case starts.
        check("expect-pose", "expect_pose_of_the_firmware", kReference,
              {"delay: 10ms", "expect-pose: {source: firmware, x_m: 0, y_m: 0.2, tol_m: 0.05}"},
              R"(expected the firmware pose within 0\.05 m of \(0\.0000, 0\.2000\); got \(0\.0000, 0\.0000\) )"
              R"(theta 0\.0000 rad, 0\.2000 m away)"),
        // An erased EEPROM reads 0xff; nothing writes it.
        check("expect-eeprom", "expect_eeprom_bin", kEcho, {"delay: 1ms", "expect-eeprom: {bin: zeros.bin}"},
              R"(EEPROM byte 0x000: expected 0x00, got 0xff)")
            .with_file("zeros.bin", std::string(1024, '\0')),
        check("expect-eeprom", "expect_eeprom_log", kEcho, {"delay: 1ms", "expect-eeprom: {log: one.csv, tol_m: 0.01}"},
              R"(the EEPROM log has 0 samples, one\.csv has 1)")
            .with_file("one.csv", "sample,t_s,x_m,y_m\n0,0.1,0,0\n"),
        check("expect-compare", "expect_compare_without_a_log", kEcho,
              {"delay: 1ms", "expect-compare: {case: 1, max_rms_m: 1}"}, R"(the EEPROM log is empty: nothing to compare)"),
        // loop_fixture.c: compute 11 cycles (0.6875 us), period 18 (1.125 us):
        // 1 ms (16,000 cycles) holds 888 iterations.
        check("expect-loop", "expect_loop_compute", kLoop,
              {"write-serial: \"x\"", "delay: 1ms", "expect-loop: {max_us: 0.5}"},
              R"(expected max_us in \[-, 0\.5\], got 0\.7 \((\d+) iterations\))")
            .measuring(885, 890),
        check("expect-loop", "expect_loop_period", kLoop,
              {"write-serial: \"x\"", "delay: 1ms", "expect-loop: {period_mean_us: [2, 3]}"},
              R"(expected period_mean_us in \[2, 3\], got 1\.1 \((\d+) iterations\))")
            .measuring(885, 890),
        check("expect-loop", "expect_loop_before_an_iteration", kLoop, {"write-serial: \"x\"", "expect-loop: {max_us: 100}"},
              R"(no complete control-loop iteration was seen)"),
        // At most 1,344 edges/s x 0.05 s = 67 edges, one INT0 each.
        check("expect-isr", "expect_isr_count", kDrive, {"delay: 50ms", "expect-isr: {vector: INT0, min_count: 100000}"},
              R"(expected INT0 to run at least 100000 times, it ran (\d+))")
            .measuring(1, 67),
        // An edge early in a 20,000-cycle off window waits more than 10,000
        // cycles, and no edge waits much longer than the window.
        check("expect-isr", "expect_isr_latency", kDrive,
              {"delay: 100ms", "expect-isr: {vector: INT0, max_latency_cycles: 10000}"},
              R"(expected INT0 entry latency <= 10000 cycles, worst (\d+) cycles)")
            .measuring(10001, 20100),
        // INT1: JMP 3 + 5 NOPs + RETI 4 = 12 cycles.
        check("expect-isr", "expect_isr_duration", kDrive,
              {"delay: 50ms", "expect-isr: {vector: INT1, max_duration_cycles: 11}"},
              R"(expected INT1 duration <= 11 cycles, longest 12 cycles)"),
        check("expect-isr", "expect_isr_never_enabled", kDrive, {"delay: 1ms", "expect-isr: {vector: TIMER1_OVF}"},
              R"(interrupt TIMER1_OVF never ran)"),
        check("expect-no-torn-reads", "torn_read_of_ticks", kRace, {"delay: 50ms", "expect-no-torn-reads: [ticks]"},
              R"(torn values observed: read torn of ticks at 0x[0-9a-f]{4} \((\d+)x\) \(isr\.md lists them\))")
            .measuring(1, 1e9),
        // Past 60 % of full speed (about 63 ms in) an edge comes within 20,000
        // cycles of the last, so an off window can hold two of a wheel's.
        check("expect-encoders", "encoder_edges_lost", kDrive, {"delay: 150ms", "expect-encoders: {max_lost: 0}"},
              R"(expected at most 0 lost encoder edges, (\d+) were lost)")
            .measuring(1, 200),
    };
}

// --- plant signals and faults ----------------------------------------------------
std::vector<FailingCase> plant_cases() {
    // drive_fixture: both wheels forward at full drive from reset. The motors'
    // no-load speeds differ by 0.4 % (plant/params/default.yaml), so without
    // a fault the two wheels turn alike and the robot drives straight.
    return {
        // Top speed 0.708 m/s (210 RPM, r = 0.0322 m): at most 3.5 cm in 50 ms.
        check("wait-until", "wait_until_too_far", kDrive, {"wait-until: {signal: x_m, op: \">=\", value: 1, timeout: 50ms}"},
              R"(expected x_m >= 1 within 0\.050 s; it was (0\.\d+))")
            .measuring(0.001, 0.0354),
        check("expect", "expect_between", kDrive, {"delay: 1ms", "expect: {signal: duty1, between: [0, 0.5]}"},
              R"(expected duty1 in \[0, 0\.5\], got 1)"),
        check("expect", "expect_op", kDrive, {"delay: 1ms", "expect: {signal: dir2, op: \"==\", value: 0}"},
              R"(expected dir2 == 0, got 1)"),
        // Half of the right encoder's edges missed: ~100 when the left has 200
        // (binomial, standard deviation 7); ~200 without the fault.
        action("inject", 0, "inject_drops_edges", kDrive,
               {"inject: {encoder: right, drop: 0.5}",
                "wait-until: {signal: left.edges, op: \">=\", value: 200, timeout: 500ms}",
                "expect: {signal: right.edges, op: \">=\", value: 150}"},
               R"(expected right.edges >= 150, got (\d+))")
            .measuring(70, 130),
        // At 150 ms the wheels turn at 90 % of 22 rad/s; a held shaft does not.
        action("stall", 1, "stall_holds_the_wheel", kDrive,
               {"delay: 150ms", "stall: {motor: left, for: 1s}", "delay: 5ms",
                "expect: {signal: left.wheel_rad_s, op: \">\", value: 5}"},
               R"(expected left.wheel_rad_s > 5, got 0)"),
        // 6.1 V less R_b I without the fault; 2 V plus or minus R_b I with it.
        action("battery", 1, "battery_at_two_volts", kDrive,
               {"delay: 150ms", "battery: {volts: 2}", "delay: 5ms", "expect: {signal: vbatt_V, op: \">\", value: 4}"},
               R"(expected vbatt_V > 4, got (\d\.\d+))")
            .measuring(1, 3),
        // The right wheel's rolling lost, the left one turns the robot
        // clockwise at r w_left / 2L = 0.0322 m x 19.5..22 rad/s / 0.128 m =
        // 4.9..5.5 rad/s: 0.49..0.55 rad in 100 ms. (omega_rad_s would not
        // show it: it is the wheels' rolling, traction not applied.)
        action("slip", 1, "slip_turns_the_robot", kDrive,
               {"delay: 150ms", "slip: {wheel: right, traction: 0}", "delay: 100ms",
                "expect: {signal: theta_rad, between: [-0.05, 0.05]}"},
               R"(expected theta_rad in \[-0\.05, 0\.05\], got (-0\.\d+))")
            .measuring(-0.55, -0.49),
        // Within tol_m of the origin, but turned by 1 rad: the heading fails.
        action("push", 0, "push_turns_the_robot", kEcho,
               {"push: {dy_m: 0.05, dtheta_rad: 1}",
                "expect-pose: {x_m: 0, y_m: 0, tol_m: 0.1, theta_rad: 0, tol_rad: 0.5}"},
               R"(expected the truth pose within 0\.1 m of \(0\.0000, 0\.0000\), theta 0\.0000 \+- 0\.5; )"
               R"(got \(0\.0000, 0\.0500\) theta 1\.0000 rad, 0\.0500 m away)"),
        // echo_fixture leaves the robot standing. A tape along the x axis under
        // it: the offset from the wheel axle's middle is 0 until the push
        // moves the robot 5 cm to the left (-0.05). Over both halves the mean is -0.025; restarted after
        // the push, -0.05.
        action("measure", 3, "measure_restarts", kEcho,
               {"measure: {signal: line_offset_m}", "delay: 100ms", "push: {dy_m: 0.05}", "measure: {signal: line_offset_m}",
                "delay: 100ms", "expect-stats: {signal: line_offset_m, mean: [-0.03, 0.03]}"},
               R"(expected the mean in \[-0\.03, 0\.03\]; line_offset_m over \d+ samples: rms [\d.e-]+, mean )"
               R"((-0\.0\d+), min .*)")
            .measuring(-0.05, -0.05)
            .in_world(kTapeAlongX),
        // 200 truth samples (one a millisecond) of an offset of -0.02 m.
        check("expect-stats", "expect_stats_rms", kEcho,
              {"measure: {signal: line_offset_m}", "delay: 200ms", "expect-stats: {signal: line_offset_m, rms_max: 0.001}"},
              R"(expected rms <= 0\.001; line_offset_m over \d+ samples: rms (0\.0\d+), mean .*)")
            .measuring(0.02, 0.02)
            .in_world(kTapeAlongX + "start: {x_m: 0, y_m: 0.02, heading_deg: 0}\n"),
        // The same offset, -0.02 m throughout: outside a range of [-0.01, 0.01].
        check("expect-stats", "expect_stats_range", kEcho,
              {"measure: {signal: line_offset_m}", "delay: 50ms", "expect-stats: {signal: line_offset_m, range: [-0.01, 0.01]}"},
              R"(expected every sample in \[-0\.01, 0\.01\]; line_offset_m over \d+ samples: rms [\d.e-]+, mean [-\d.e]+, )"
              R"(min (-0\.0\d+), max .*)")
            .measuring(-0.02, -0.02)
            .in_world(kTapeAlongX + "start: {x_m: 0, y_m: 0.02, heading_deg: 0}\n"),
        // A marker 50 mm ahead of the axle, over a tape 20 mm to the right.
        check("expect", "expect_part_column", kEcho, {"delay: 10ms", "expect: {signal: nose.line_offset_m, op: \">\", value: 0}"},
              R"(expected nose\.line_offset_m > 0, got (-0\.0\d+))")
            .measuring(-0.02, -0.02)
            .in_world(kTapeAlongX + "start: {x_m: 0, y_m: 0.02, heading_deg: 0}\n")
            .on_board(kThesisBoardWith + "parts:\n  - {name: nose, type: marker, x_mm: 50}\n"),
        // echo_fixture leaves the robot standing: set down at (0.4, -0.2),
        // heading 90 degrees, it is 0.447 m from the origin.
        action("place", 0, "place_moves_the_robot", kEcho,
               {"place: {x_m: 0.4, y_m: -0.2, heading_deg: 90}",
                "expect-pose: {x_m: 0, y_m: 0, tol_m: 0.1}"},
               R"(expected the truth pose within 0\.1 m of \(0\.0000, 0\.0000\); got \(0\.4000, -0\.2000\) )"
               R"(theta 1\.5708 rad, 0\.4472 m away)"),
        // echo_fixture leaves the robot standing at the origin; the box's
        // near face, 0.5 m ahead, slides 0.3 m toward it over 100 ms: the
        // nearest wall is then 0.2 m from the axle.
        action("move-obstacle", 0, "move_obstacle_brings_the_box", kEcho,
               {"move-obstacle: {name: box, dx_m: -0.3, over: 100ms}", "delay: 150ms",
                "expect: {signal: wall_distance_m, op: \">\", value: 0.4}"},
               R"(expected wall_distance_m > 0\.4, got (0\.\d+))")
            .measuring(0.2, 0.2)
            .in_world("walls:\n  - {polygon_m: [[0.5, -0.1], [0.7, -0.1], [0.7, 0.1], [0.5, 0.1]], name: box}\n"),
        // A reset clears DDRB and PORTB: D12 is an input again, read low.
        action("reset", 1, "reset_clears_the_pins", kDrive, {"delay: 1ms", "reset", "expect-pin: {pin: 12, value: 1}"},
               R"(expected pin 12 = 1, got 0)"),
    };
}

// --- expect-compare's tolerances, on the reference's own EEPROM log ---------------
std::vector<FailingCase> compare_cases() {
    // Case 1 logs every 0.1 s: 1 s into it, ~10 samples. The same log and
    // host simulation pass under 1 m (step 5) and fail under 0.1 mm (step 6):
    // the tolerance alone decides, and the failure reports the same numbers.
    const std::vector<std::string> run = {"delay: 100ms", "write-serial: \"1\"", "wait-serial: {text: \"0.6m\", timeout: 6s}",
                                          "delay: 1s", "expect-compare: {case: 1, max_rms_m: 1, max_endpoint_m: 1}"};
    const auto same_numbers = [](const char* which) {
        return [which](const json& result) {
            const std::regex number(std::string(which) + R"( (\d\.\d{4}) m)");
            std::smatch passed, failed;
            const std::string p = result["steps"][4]["message"].get<std::string>();
            const std::string f = result["steps"][5]["message"].get<std::string>();
            ASSERT_TRUE(std::regex_search(p, passed, number)) << p;
            ASSERT_TRUE(std::regex_search(f, failed, number)) << f;
            EXPECT_EQ(passed[1].str(), failed[1].str()) << p << "\n" << f;
        };
    };
    std::vector<std::string> rms = run;
    rms.emplace_back("expect-compare: {case: 1, max_rms_m: 0.0001}");
    std::vector<std::string> endpoint = run;
    endpoint.emplace_back("expect-compare: {case: 1, max_rms_m: 1, max_endpoint_m: 0.0001}");
    std::vector<FailingCase> cases = {
        check("expect-compare", "expect_compare_rms", kReference, rms,
              R"(EEPROM log vs host simulation \(case 1\): rms (\d\.\d{4}) m \(max 0\.0001\), endpoint \d\.\d{4} m)")
            .measuring(0.0002, 0.05)
            .within("8s"),
        check("expect-compare", "expect_compare_endpoint", kReference, endpoint,
              R"(EEPROM log vs host simulation \(case 1\): rms \d\.\d{4} m \(max 1\), endpoint (\d\.\d{4}) m \(max 0\.0001\))")
            .measuring(0.0002, 0.05)
            .within("8s"),
    };
    cases[0].also = same_numbers("rms");
    cases[1].also = same_numbers("endpoint");
    return cases;
}

TEST(ScenarioStepFailures, EveryStepKindHasACaseThatMakesItFail) {
    std::set<std::string> covered;
    for (const auto& cases : {serial_and_pin_cases(), firmware_check_cases(), plant_cases(), compare_cases()}) {
        for (const FailingCase& c : cases) covered.insert(c.kind);
    }
    for (const tools::scenario::StepInfo& s : tools::scenario::step_catalog()) {
        EXPECT_EQ(covered.count(std::string(s.kind)), 1U) << "no case makes step kind '" << s.kind << "' fail";
    }
}

TEST(ScenarioStepFailures, SerialAndPinSteps) { expect_each_fails(serial_and_pin_cases()); }
TEST(ScenarioStepFailures, FirmwareAndRobotChecks) { expect_each_fails(firmware_check_cases()); }
TEST(ScenarioStepFailures, PlantSignalsAndFaults) { expect_each_fails(plant_cases()); }
TEST(ScenarioStepFailures, CompareTolerances) { expect_each_fails(compare_cases()); }

// A part's column its type does not have, and a world signal without a
// world, are refused before the run (exit 2), naming the line.
TEST(ScenarioSignals, AColumnTheRobotLacksIsRefusedBeforeTheRun) {
    TempDir dir;
    fs::copy_file(test_firmware_dir() / kDrive, dir / kDrive);
    write_text(dir, "board.yaml", kThesisBoardWith + "parts:\n  - {name: nose, type: marker, x_mm: 50}\n");
    write_text(dir, "s.yaml", "firmware: " + kDrive + "\nboard: board.yaml\ntimeout: 1s\nsteps:\n"
                              "  - delay: 1ms\n  - expect: {signal: nose.volts, op: \">\", value: 0}\n");
    ProcessResult r = scenario(sh_quote((dir / "s.yaml").string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("s.yaml:6: key 'expect.signal': this robot has no signal 'nose.volts' (its world and parts "
                         "give: nose.line_offset_m, nose.reflectance)"),
              std::string::npos)
        << r.err;
    write_text(dir, "w.yaml", "firmware: " + kDrive + "\ntimeout: 1s\nsteps:\n  - measure: {signal: wall_distance_m}\n");
    r = scenario(sh_quote((dir / "w.yaml").string()) + " --out " + sh_quote((dir / "out2").string()));
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("w.yaml:4: key 'measure.signal': this robot has no signal 'wall_distance_m' (its world and "
                         "parts give: none)"),
              std::string::npos)
        << r.err;
}

}  // namespace
}  // namespace ddmr::test
