#include "run_outputs.hpp"

#include <cstdio>
#include <exception>
#include <vector>

#include "callgrind_output.hpp"
#include "firmware_run_json.hpp"
#include "function_profile_output.hpp"
#include "profile_lines.hpp"
#include "race_report.hpp"

namespace ddmr::tools {

using hil::Cycles;
using nlohmann::json;

void tag_eeprom_writes(hil::LoopProfiler& loop, hil::RobotRig& rig) {
    std::vector<Cycles> write_cycles;
    for (const auto& w : rig.eeprom_timing().writes()) write_cycles.push_back(w.cycle);
    loop.tag_eeprom_writes(write_cycles);
}

ProfileOutputs profile_outputs(hil::Session& session, const RunPlan& plan, const FirmwareRunOptions& options,
                               Profilers& profilers, FirmwareRunResult& result) {
    ProfileOutputs out;
    hil::RobotRig& rig = session.rig();
    const uint32_t clock_hz = session.core().clock_hz();
    if (profilers.loop) {
        tag_eeprom_writes(*profilers.loop, rig);
        result.loop_profile = profilers.loop->iterations();
        out.loop_profile = loop_profile_json(result.loop_profile, clock_hz);
        out.loop_profile["eeprom_writes_all_tagged"] = rig.eeprom_timing().all_writes_recorded();
        out.loop_profile["mark"] = plan.loop_mark_name;
        out.loop_profile_csv = loop_profile_table(result.loop_profile, clock_hz);
    }
    if (profilers.functions) {
        const hil::FunctionProfiler& fp = *profilers.functions;
        FunctionProfileContext context{clock_hz, plan.loop_mark_name, {}, {}};
        try {
            context.lines = profile_lines(plan.elf.path(), fp);
        } catch (const std::exception& e) {
            context.lines_error = e.what();
            std::fprintf(stderr, "ddmr-hil: warning: no source lines in the profile: %s\n", e.what());
        }
        out.function_profile = function_profile_json(fp, context);
        out.function_profile["callgrind"] = {{"file", "callgrind.out"}, {"scope", callgrind_scope(fp)}};
        out.function_profile_txt = function_profile_text(fp, context);
        out.callgrind_txt = callgrind_profile(fp, context, plan.elf.path().string());
        result.function_profile_top = function_profile_top(fp, context, options.profile_top);
    }
    return out;
}

IsrOutputs isr_outputs(hil::Session& session) {
    IsrOutputs out;
    hil::IsrMonitor* monitor = session.isr_monitor();
    hil::RaceDetector* races = session.race_detector();
    if (monitor == nullptr) return out;
    const hil::IsrSummary s = monitor->summary();
    out.isr = isr_json(s);
    out.markdown = hil::to_markdown(s);
    out.summary = {{"isr_share", static_cast<double>(s.isr_cycles) /
                                     static_cast<double>(std::max<Cycles>(1, s.observed_cycles()))},
                   {"details", "isr.json"}};
    if (races != nullptr) {
        const RaceReport race = race_report(*races, session.elf());
        out.isr["races"] = race.json;
        out.markdown += race.markdown;
        out.summary["torn_reads"] = torn_reads_summary(*races);
        out.summary["races"] = {{"torn_observed", race.json["torn_observed"]},
                                {"torn_possible", race.json["torn_possible"]},
                                {"stale_reads", race.json["stale_reads"]}};
    }
    return out;
}

}  // namespace ddmr::tools
