#pragma once
// What a run's instruments give at its end, for `ddmr-hil run` and every
// front end over FirmwareRun: the profilers of --profile and their outputs
// (loop_profile.csv, profile.json, profile.txt, callgrind.out), and the ISR
// monitor's and race detector's (isr.json, isr.md), with their summary.json
// parts.

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

#include "firmware_run.hpp"
#include "firmware_run_plan.hpp"
#include "hil/function_profiler.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/session.hpp"

namespace ddmr::tools {

/// The profilers of --profile: the loop profile (compute / wait / period
/// per iteration) and the function profile, whose control-loop scope uses
/// the loop profiler's iterations; built before the first instruction, they
/// see the whole stack.
struct Profilers {
    std::optional<hil::LoopProfiler> loop;
    std::optional<hil::FunctionProfiler> functions;
    Profilers(hil::AvrCore& core, const std::optional<hil::ElfSymbol>& mark) {
        if (!mark) return;
        loop.emplace(core, *mark);
        functions.emplace(core);
        // The compute scope: the loop without the wait in its mark (delay() and what it calls).
        functions->set_wait_function(functions->map().at(mark->address));
        loop->set_iteration_listener([this](bool completed) { functions->on_loop_boundary(completed); });
    }
};

/// The profile outputs of --profile (loop_profile.csv, profile.json,
/// profile.txt, callgrind.out) and their summary.nlohmann::json parts.
struct ProfileOutputs {
    nlohmann::json loop_profile = nullptr;
    std::string loop_profile_csv;
    nlohmann::json function_profile = nullptr;
    std::string function_profile_txt;
    std::string callgrind_txt;
};

/// Marks the loop profile's iterations that started an EEPROM write in their
/// compute (the first EepromWriteTiming::kMaxRecordedWrites writes).
void tag_eeprom_writes(hil::LoopProfiler& loop, hil::RobotRig& rig);

/// Tags the loop profile's EEPROM writes and makes the profile outputs;
/// fills result.loop_profile and result.function_profile_top.
ProfileOutputs profile_outputs(hil::Session& session, const RunPlan& plan, const FirmwareRunOptions& options,
                               Profilers& profilers, FirmwareRunResult& result);

/// summary.json's `isr` and isr.nlohmann::json / isr.md, from the instruments that were on.
struct IsrOutputs {
    nlohmann::json isr = nullptr;          ///< isr.json
    nlohmann::json summary = nullptr;      ///< summary.json's `isr`
    std::string markdown;        ///< isr.md
};

IsrOutputs isr_outputs(hil::Session& session);

}  // namespace ddmr::tools
