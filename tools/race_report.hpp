#pragma once
// The race detector's findings (hil/race_detector.hpp) as isr.json's
// "races" object, summary.json's per-variable torn-read counts and a
// Markdown section of isr.md, with functions and source lines resolved.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>

#include "hil/function_map.hpp"
#include "hil/race_detector.hpp"

namespace ddmr::tools {

/// The main program's direct loads (LDS) and stores (STS) of one shared variable.
struct MainSiteCounts {
    std::size_t loads = 0;
    std::size_t stores = 0;
};

/// Names for flash addresses: the function (from the symbol table) and, when
/// the ELF has line information, the source file:line; and the main
/// program's accesses of each shared variable (found once, with the functions).
struct CodeNames {
    const hil::FunctionMap* functions = nullptr;
    std::map<uint32_t, std::string> lines;  ///< from source_lines()
    std::map<std::size_t, MainSiteCounts> main_sites;  ///< by DataObjects index; from main_site_counts()
    std::string function(uint32_t pc) const;
    std::string line(uint32_t pc) const;  ///< "" when unknown
};

/// Every flash address the report names (to resolve source lines in one go).
std::vector<uint32_t> race_report_pcs(const hil::RaceDetector& races);

/// The main program's LDS / STS of every shared variable (RaceDetector::main_sites).
std::map<std::size_t, MainSiteCounts> main_site_counts(const hil::RaceDetector& races,
                                                      const hil::FunctionMap& functions);

/// isr.json's "races": shared variables, torn accesses, stale reads, counts.
nlohmann::json races_json(const hil::RaceDetector& races, const CodeNames& names);

/// summary.json's "torn_reads": per ISR-written variable of 2..8 bytes (named
/// even without splits) its main-program reads split by an ISR that writes
/// it ("split_reads"), torn by it ("torn") and with a value it never held
/// ("visible").
nlohmann::json torn_reads_summary(const hil::RaceDetector& races);

/// The "Shared variables and races" section of isr.md.
std::string races_markdown(const hil::RaceDetector& races, const CodeNames& names);

/// The report of `races` on `elf`: isr.json's "races" and isr.md's section,
/// with function names and source lines (when avr-addr2line is missing or
/// fails, a warning on stderr and no lines).
struct RaceReport {
    nlohmann::json json;
    std::string markdown;
};
RaceReport race_report(const hil::RaceDetector& races, const hil::ElfImage& elf);

/// Number of observed torn accesses (reads and writes) of the named
/// variables (all when `variables` is empty).
uint64_t observed_torn(const hil::RaceDetector& races, const std::vector<std::string>& variables = {});

}  // namespace ddmr::tools
