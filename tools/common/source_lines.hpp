#pragma once
// Source file:line of flash addresses, from the ELF's debug information, by
// binutils-avr's avr-addr2line (it reads DWARF and the stabs that Debian's
// avr-gcc 5.4 writes for -g, which the Arduino build uses). One process for
// all the addresses of a report.

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace ddmr::tools {

/// The program that resolves the lines (avr-addr2line on PATH), or empty.
std::filesystem::path addr2line_program();

/// Where a flash address is in the source, as avr-addr2line -f -i says.
struct SourceLocation {
    std::string file;      ///< source file of the innermost (inlined) code
    uint32_t line = 0;     ///< its line, >= 1
    std::string function;  ///< the outermost function: the symbol the code is in
};

/// The location of each flash byte address of `pcs` that the ELF has line
/// information for (others are absent). Throws std::runtime_error if
/// avr-addr2line is missing or fails on the file.
std::map<uint32_t, SourceLocation> source_locations(const std::filesystem::path& elf,
                                                    const std::vector<uint32_t>& pcs);

/// "file:line" for each flash byte address of `pcs` that the ELF has line
/// information for (addresses without any are absent from the result: an
/// ELF built without -g gives an empty map). Throws std::runtime_error if
/// avr-addr2line is missing or fails on the file.
std::map<uint32_t, std::string> source_lines(const std::filesystem::path& elf, const std::vector<uint32_t>& pcs);

}  // namespace ddmr::tools
