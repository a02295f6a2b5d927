#pragma once
// Runs the reference firmware closed-loop on a RobotRig through one case and
// keeps what the closed-loop tests check.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "hil/eeprom_log.hpp"
#include "hil/firmware_report.hpp"
#include "hil/loop_tracer.hpp"
#include "hil/robot_rig.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {

struct RigRun {
    bool report_complete = false;
    std::string text;
    std::vector<hil::UartByte> bytes;
    hil::FirmwareReport report;
    std::array<hil::EncoderChannelStats, 2> encoder{};
    std::array<std::vector<hil::Cycles>, 2> isr_entries{};
    plant::Pose end_truth{};
    double farthest_m = 0.0;  ///< the truth's greatest distance from the start (sampled every 1 ms)
    std::array<double, 2> motor_angle_rad{};  ///< each motor shaft's angle at the end (the plant's)
    hil::Cycles ready_cycle = 0;
    hil::Cycles max_latency = 0;
    std::vector<hil::EepromLogSample> log;
    std::vector<hil::Cycles> iteration_cycles;  ///< t increased (first 1200)
    double mean_period_s = 0.0;
    double ex = 0, ey = 0;  ///< the firmware's Ex, Ey when "END" was sent
};

inline RigRun run_rig_case(char case_byte, const hil::RigConfig& config = {}, double limit_s = 40.0) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::RobotRig rig(elf, config);
    hil::FirmwareReportParser parser(case_byte == '1');
    RigRun run;
    const auto ex = rig.variables().lookup("Ex", hil::VarType::kFloat);
    const auto ey = rig.variables().lookup("Ey", hil::VarType::kFloat);
    rig.uart().set_listener([&](const hil::UartByte& b) {
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (parser.report().ended && run.ex == 0 && run.ey == 0) {
            run.ex = rig.variables().read_as<float>(ex);
            run.ey = rig.variables().read_as<float>(ey);
        }
        if (parser.complete() || parser.error()) rig.core().request_stop();
    });
    hil::LoopTracer tracer(rig.variables(), {"t", hil::VarType::kFloat}, {{"t", hil::VarType::kFloat}});
    double last_t = 0;
    tracer.set_sink([&](hil::Cycles c, const std::vector<double>& v) {
        if (v[0] > last_t) run.iteration_cycles.push_back(c);
        last_t = v[0];
    });
    rig.coupler().set_boundary_hook([&](hil::Cycles c) { tracer.poll(c); });
    rig.coupler().set_truth_sink([&](const hil::TruthSample& t) {
        run.farthest_m = std::max(run.farthest_m, std::hypot(t.x_m, t.y_m));
    });
    const auto limit = hil::s_to_cycles(limit_s, kUnoClockHz);
    if (rig.core().run_until_return_from(elf.require("delay"), limit) == hil::RunStop::kCondition) {
        run.ready_cycle = rig.core().cycle();
        rig.uart().send(std::string(1, case_byte));
        rig.core().run_until(limit);
    }
    run.report_complete = parser.complete();
    run.report = parser.report();
    run.text = rig.uart().text();
    run.bytes = rig.uart().received();
    for (unsigned ch = 0; ch < 2; ++ch) {
        run.encoder[ch] = rig.encoders().stats(ch);
        run.isr_entries[ch] = rig.encoders().isr_entries(ch);
    }
    run.end_truth = rig.robot().pose();
    for (std::size_t m = 0; m < 2; ++m) run.motor_angle_rad[m] = rig.robot().motor_angle_rad(m);
    run.max_latency = rig.coupler().max_input_latency_cycles();
    const auto timing = hil::eeprom_log_timing(rig.eeprom_timing().latest_writes(), run.ready_cycle, kUnoClockHz, 1024);
    run.log = hil::decode_eeprom_log(rig.eeprom().read_all(), timing.sample_count, timing.times_s);
    const auto& it = run.iteration_cycles;
    if (it.size() > 1) {
        run.mean_period_s = hil::cycles_to_s(it.back() - it.front(), kUnoClockHz) / static_cast<double>(it.size() - 1);
    }
    return run;
}

}  // namespace ddmr::test
