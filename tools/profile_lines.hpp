#pragma once
// Source lines of a function profile (hil::FunctionProfiler): the flash
// addresses it counted cycles at, and its call sites, resolved to file:line
// once, when the profile is written (common/source_lines: avr-addr2line reads
// the ELF's DWARF, or the stabs Debian's avr-gcc 5.4 writes for -g; the
// reference ELF's lines are in its stabs, its .debug_line is empty).
//
// An address keeps its line only if addr2line's outermost function there is
// the FunctionMap's function (its name or an alias): stabs give every address
// after the last function they describe that function's last line (on the
// reference ELF the whole of libgcc's and libm's float code would land on
// `_GLOBAL__I_...`'s line 79). Those, and every address without a line
// (hand-written assembly, the start-up code, an ELF without -g), are reported
// as "(no line info) function+offset", never dropped.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hil/function_profiler.hpp"

namespace ddmr::tools {

struct SourceLine {
    std::string file;   ///< as the debug information names it (absolute for the Arduino build)
    uint32_t line = 0;  ///< >= 1
};

/// The line of each flash byte address that has one.
using AddressLines = std::map<uint32_t, SourceLine>;

/// The addresses whose lines the profile's outputs need: every instruction
/// that ran (whole run) and every call site.
std::vector<uint32_t> profiled_addresses(const hil::FunctionProfiler& profiler);

/// The lines of profiled_addresses() in `elf`, checked against the profiler's
/// function map as above. Throws std::runtime_error if avr-addr2line is
/// missing or fails.
AddressLines profile_lines(const std::filesystem::path& elf, const hil::FunctionProfiler& profiler);

/// One source line's self cycles in a scope.
struct LineCycles {
    SourceLine where;
    hil::Cycles self_cycles = 0;
    std::vector<hil::FunctionId> functions;  ///< whose code it is, by address (inlining: several)
};

/// One instruction without a line: its self cycles in a scope.
struct UnlinedCycles {
    uint32_t address = 0;  ///< flash byte address
    hil::FunctionId function = 0;
    hil::Cycles self_cycles = 0;
};

/// A scope's self cycles by source line.
struct ScopeLines {
    std::vector<LineCycles> lines;       ///< by self cycles, largest first, then file, then line
    std::vector<UnlinedCycles> unlined;  ///< by self cycles, largest first, then address
    hil::Cycles line_cycles = 0;         ///< sum over lines
    hil::Cycles unlined_cycles = 0;      ///< sum over unlined: line_cycles + this = the scope's cycles
};

ScopeLines scope_lines(const hil::ProfileScope& scope, const hil::FunctionMap& map, const AddressLines& lines);

/// "(no line info) name+0x1a" (the raw symbol name; "+0x0" at the entry).
std::string unlined_label(const hil::FunctionMap& map, uint32_t address);

}  // namespace ddmr::tools
