#include "scenario/step_catalog.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <string>

namespace ddmr::tools::scenario {

const std::vector<StepInfo>& step_catalog() {
    static const std::vector<StepInfo> steps = {
        {"delay", "D (a duration: 10ms, 2s, 250us)", "let the AVR run for D", "delay: 10ms"},
        {"write-serial", "\"text\"", "send the bytes to the firmware's RX at the adapter's baud rate", "write-serial: \"1\""},
        {"wait-serial", "\"text\" | {text, timeout}",
         "run until the text has been received after the previous wait-serial's match (fails at its timeout, or the "
         "scenario's)",
         "wait-serial: {text: \"0.6m\", timeout: 8s}"},
        {"expect-serial", "regex", "the last 64 KiB received contain a match", "expect-serial: \"m\""},
        {"fail-serial", "regex", "from now on, a received line that matches fails the scenario", "fail-serial: \"ERROR\""},
        {"wait-pin", "{pin, value, timeout}", "run until the pin has the level", "wait-pin: {pin: 13, value: 0, timeout: 1s}"},
        {"expect-pin", "{pin, value}", "the pin's level now", "expect-pin: {pin: 13, value: 0}"},
        {"expect-pwm", "{pin, duty, tol}", "a motor driver input's PWM duty now (decoded from the timer)",
         "expect-pwm: {pin: 10, duty: 0, tol: 0.01}"},
        {"expect-part", "{part, port, value}", "a part's output level now (board file `parts:`)",
         "expect-part: {part: shield, port: Q2, value: 1}"},
        {"expect-warning", "regex", "a wiring warning so far matches", "expect-warning: \"never\""},
        {"expect-var", "{name, op, value, type}", "a firmware global, by ELF symbol, now (checked before the run)",
         "expect-var: {name: Count1, type: int16, op: \">=\", value: 0}"},
        {"expect-pose", "{source, x_m, y_m, tol_m, theta_rad, tol_rad}",
         "the pose (plant truth, or the firmware's Ex, Ey, Theta) is within tol_m of (x_m, y_m)",
         "expect-pose: {x_m: 0, y_m: 0, tol_m: 0.01}"},
        {"expect-eeprom", "{bin} | {log, tol_m}", "the EEPROM equals a file, or its decoded log matches a CSV",
         "expect-eeprom: {log: golden/case1_eeprom_log.csv, tol_m: 0.01}"},
        {"expect-compare", "{case, max_rms_m, max_endpoint_m}",
         "the EEPROM log against the host simulation of the same robot", "expect-compare: {case: 1, max_rms_m: 0.05}"},
        {"expect-loop",
         "{max_us, p99_us, mean_us, period_max_us, period_p99_us, period_mean_us, include_eeprom_writes}",
         "the control loop's compute and period statistics so far (bounds X or [min, max])",
         "expect-loop: {max_us: 20000}"},
        {"expect-isr", "{vector, min_count, max_latency_cycles, max_duration_cycles}",
         "an interrupt vector's count, latency and duration so far", "expect-isr: {vector: INT0, min_count: 0}"},
        {"expect-no-torn-reads", "(no value) | [variable, ...]",
         "no torn access to an ISR-shared variable (those named, or any) so far", "expect-no-torn-reads"},
        {"expect-encoders", "{max_lost}", "encoder edges lost at the pins so far", "expect-encoders: {max_lost: 0}"},
        {"wait-until", "{signal, op, value, timeout}", "run until a signal holds signal op value",
         "wait-until: {signal: vbatt_V, op: \">\", value: 1, timeout: 1s}"},
        {"expect", "{signal, op, value} | {signal, between: [A, B]}", "a signal holds now",
         "expect: {signal: x_m, between: [-1, 1]}"},
        {"measure", "{signal}", "from now on, collect the signal's truth samples (1 ms) for expect-stats",
         "measure: {signal: line_offset_m}"},
        {"expect-stats", "{signal, rms_max, abs_max, mean, range, min_samples}",
         "the signal's samples since its measure step: rms, largest magnitude, mean [A, B], every sample in [A, B]",
         "expect-stats: {signal: line_offset_m, rms_max: 0.006, abs_max: 0.015}"},
        {"inject", "{encoder, drop, for}", "the Hall sensor misses each edge with a probability (seeded)",
         "inject: {encoder: right, drop: 0.1, for: 1s}"},
        {"stall", "{motor, for}", "the motor's shaft is held", "stall: {motor: left, for: 100ms}"},
        {"battery", "{volts, for}", "the battery becomes an ideal source of this voltage", "battery: {volts: 5, for: 1s}"},
        {"slip", "{wheel, traction, for}", "only this fraction of the wheel's rolling moves the robot",
         "slip: {wheel: right, traction: 0.5, for: 1s}"},
        {"push", "{dx_m, dy_m, dtheta_rad, over}",
         "the robot is displaced (at once, or evenly over `over`); odometry does not see it", "push: {dx_m: 0.01}"},
        {"place", "{x_m, y_m, heading_deg}", "the robot is set down at this pose; odometry does not see it",
         "place: {x_m: 0.5, y_m: 0, heading_deg: 90}"},
        {"move-obstacle", "{name, dx_m, dy_m, over}",
         "a named obstacle of the world moves by (dx_m, dy_m), at once or evenly over `over`",
         "move-obstacle: {name: box, dy_m: 0.3, over: 1s}"},
        {"reset", "(no value) | {}", "AVR reset, as by the RESET pin; the robot keeps moving", "reset"},
    };
    return steps;
}

const StepInfo* find_step(std::string_view kind) {
    const auto& steps = step_catalog();
    const auto it = std::find_if(steps.begin(), steps.end(), [&](const StepInfo& s) { return s.kind == kind; });
    return it == steps.end() ? nullptr : &*it;
}

std::string_view step_catalog_text() {
    static const std::string text = [] {
        std::string t = "Scenario steps (docs/scenarios.md has every key, unit and default):\n";
        for (const StepInfo& s : step_catalog()) {
            t += fmt::format("\n  {}: {}\n      {}\n      e.g.  - {}\n", s.kind, s.forms, s.what, s.example);
        }
        return t;
    }();
    return text;
}

}  // namespace ddmr::tools::scenario
