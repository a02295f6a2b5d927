#pragma once
// The profile's loop mark: the function each control-loop iteration calls
// once (hil/loop_profiler.hpp). Named by the user (--loop-mark), a sketch
// contract (loop.function) or chosen here: loop(), or delay() where LTO
// inlined loop() into main. A name is a symbol or a C++ name
// (hil::ElfImage::find_functions: "serialEventRun", "MyClass::step").
// When no mark is found, the one-line error names functions that would
// work: those main's loop calls from one place each (an Arduino main is
// `for (;;) { loop(); if (serialEventRun) serialEventRun(); }`, with
// loop()'s calls in it where LTO inlined it).

#include <string>
#include <vector>

#include "hil/elf_image.hpp"

namespace ddmr::tools {

/// The function `name` names, for a mark given by `origin` ("--loop-mark",
/// "the contract's loop.function"). Throws std::runtime_error, one line
/// naming the firmware: no such function (with suggestions), a symbol that
/// is no function with code, or several overloads (each listed).
hil::ElfSymbol resolve_loop_mark(const hil::ElfImage& elf, const std::string& name, const std::string& origin);

/// The mark of a firmware whose contract and command line name none:
/// "loop", else "delay" (said on stderr: LTO inlined loop()). Throws
/// std::runtime_error with suggestions when neither is a function.
std::string default_loop_mark(const hil::ElfImage& elf);

/// Names (as resolve_loop_mark takes them) of the functions main's loop
/// calls from one place each, in the order of their calls, at most `most`;
/// the runtime's helpers (__mulsf3, ...) left out. Where main has no loop
/// or is missing: delay and serialEventRun, those present.
std::vector<std::string> loop_mark_candidates(const hil::ElfImage& elf, std::size_t most = 6);

}  // namespace ddmr::tools
