#pragma once
// The function profile (hil::FunctionProfiler) as `ddmr-hil run --profile`
// writes it: profile.json, profile.txt and the top-N table on stdout.
//
// Each scope ("whole_run", "control_loop") lists the functions that ran in it
// (calls or cycles > 0), sorted by self cycles, largest first, ties by
// address: deterministic for the same run. Shares are of the scope's cycles;
// self_us is the function's total self time in the scope at the AVR clock.
// Each scope also has
//   call_graph     caller -> callee edges (the call sites of one caller and
//                  callee summed): calls and inclusive cycles of the calls;
//                  the caller "<spontaneous>" (no caller) is the reset (the
//                  root frame) and interrupt entries. For every function the
//                  edges into it sum to its calls and inclusive cycles.
//                  profile.txt shows it gprof-style: each function with its
//                  callers above and its callees below.
//   source_lines   self cycles per source line (profile_lines.hpp) and per
//                  instruction without one, and the share without.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hil/function_profiler.hpp"
#include "profile_lines.hpp"

namespace ddmr::tools {

/// What profile.json and the tables say about where the scopes come from.
struct FunctionProfileContext {
    uint32_t clock_hz = 0;       ///< [Hz] AVR clock, to convert cycles to us
    std::string loop_mark;       ///< the LoopProfiler's mark function (delay)
    AddressLines lines;          ///< profile_lines(); empty: every address without a line
    std::string lines_error;     ///< why `lines` is empty, if it failed (avr-addr2line missing)
};

/// A caller -> callee edge of a scope's call graph: its call sites summed.
struct FunctionEdge {
    hil::FunctionId caller = hil::CallEdge::kNoCaller;  ///< kNoCaller: <spontaneous>
    hil::FunctionId callee = 0;
    uint64_t calls = 0;
    hil::Cycles inclusive_cycles = 0;
};

/// The edges of `scope` with calls or cycles, by inclusive cycles (largest
/// first), then caller address (<spontaneous> first), then callee address.
std::vector<FunctionEdge> function_edges(const hil::FunctionProfiler& profiler, const hil::ProfileScope& scope);

/// profile.json: both scopes with every function that ran, and the shadow
/// stack's diagnostics.
nlohmann::json function_profile_json(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context);

/// profile.txt: both scopes, every function that ran, as aligned tables.
std::string function_profile_text(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context);

/// The `top_n` (>= 1) functions of both scopes by self cycles, and the
/// control loop's top_n source lines, for stdout.
std::string function_profile_top(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context,
                                 std::size_t top_n);

}  // namespace ddmr::tools
