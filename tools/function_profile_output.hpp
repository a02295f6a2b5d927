#pragma once
// The function profile (hil::FunctionProfiler) as `ddmr-hil run --profile`
// writes it: profile.json, profile.txt and the top-N table on stdout.
//
// Each scope ("whole_run", "control_loop") lists the functions that ran in it
// (calls or cycles > 0), sorted by self cycles, largest first, ties by
// address: deterministic for the same run. Shares are of the scope's cycles;
// self_us is the function's total self time in the scope at the AVR clock.

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "hil/function_profiler.hpp"

namespace ddmr::tools {

/// What profile.json and the tables say about where the scopes come from.
struct FunctionProfileContext {
    uint32_t clock_hz = 0;       ///< [Hz] AVR clock, to convert cycles to us
    std::string loop_mark;       ///< the LoopProfiler's mark function (delay)
};

/// profile.json: both scopes with every function that ran, and the shadow
/// stack's diagnostics.
nlohmann::json function_profile_json(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context);

/// profile.txt: both scopes, every function that ran, as aligned tables.
std::string function_profile_text(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context);

/// The `top_n` (>= 1) functions of both scopes by self cycles, for stdout.
std::string function_profile_top(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context,
                                 std::size_t top_n);

}  // namespace ddmr::tools
