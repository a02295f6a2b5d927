#pragma once
// The function profile (hil::FunctionProfiler) in callgrind's profile format
// (valgrind's docs/manual/cl-format.html, version 1), which KCachegrind,
// QCachegrind and callgrind_annotate read: `ddmr-hil profile` and
// `run --profile` write it as callgrind.out.
//
// One scope: the control loop (the completed iterations, as profile.json's
// control_loop) when it has any, else the whole run; `desc: Scope:` says
// which. One event, Cycles (AVR clock cycles); `positions: line`:
//   fl= / fn=      each function that ran or called in the scope (demangled
//                  name; " @0x..." added where two functions share one), in
//                  its file (the file of its first instruction with a line,
//                  "???" without any);
//   LINE CYCLES    self cycles per source line (profile_lines.hpp); the
//                  instructions without a line are line 0 of the function's
//                  file; fi= / fe= switch to the files of inlined code;
//   cfi= / cfn= / calls=COUNT LINE, then SITE_LINE INCLUSIVE
//                  each call site's calls and inclusive cycles in the scope
//                  (LINE: the callee's first line, 0 without).
// Not written: the <spontaneous> edges (reset, interrupt entries: no caller),
// and edges that made no call in the scope (a frame still open from before
// it, a branch into another function's shared tail): their cycles stay the
// callee's self cost, so the totals are exact, only the caller's inclusive
// cost in the viewer leaves them out. No `summary:`/`totals:` line: viewers
// add the cost lines up, so the total is the scope's cycles.

#include <string>

#include "function_profile_output.hpp"

namespace ddmr::tools {

/// profile.json's key of the scope callgrind_profile() writes: "control_loop"
/// if it completed an iteration, else "whole_run".
std::string callgrind_scope(const hil::FunctionProfiler& profiler);

/// callgrind.out's text; `command` is its `cmd:` line (the firmware's path).
std::string callgrind_profile(const hil::FunctionProfiler& profiler, const FunctionProfileContext& context,
                              const std::string& command);

}  // namespace ddmr::tools
