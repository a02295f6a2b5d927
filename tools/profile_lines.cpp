// Source lines of a function profile: resolution and per-scope aggregation.
#include "profile_lines.hpp"

#include <fmt/format.h>

#include <algorithm>

#include "common/source_lines.hpp"

namespace ddmr::tools {

std::vector<uint32_t> profiled_addresses(const hil::FunctionProfiler& profiler) {
    std::vector<uint32_t> pcs;
    const hil::ProfileScope all = profiler.whole_run();
    for (std::size_t word = 0; word < all.word_cycles.size(); ++word) {
        if (all.word_cycles[word] != 0) pcs.push_back(static_cast<uint32_t>(word * 2));
    }
    for (const hil::CallEdge& e : profiler.edges()) {
        if (e.site != hil::CallEdge::kNoSite) pcs.push_back(e.site);
    }
    std::sort(pcs.begin(), pcs.end());
    pcs.erase(std::unique(pcs.begin(), pcs.end()), pcs.end());
    return pcs;
}

AddressLines profile_lines(const std::filesystem::path& elf, const hil::FunctionProfiler& profiler) {
    const hil::FunctionMap& map = profiler.map();
    AddressLines out;
    for (auto& [pc, loc] : source_locations(elf, profiled_addresses(profiler))) {
        const hil::FunctionInfo& f = map.function(map.at(pc));
        const bool same_function = loc.function == f.name ||
                                   std::find(f.aliases.begin(), f.aliases.end(), loc.function) != f.aliases.end();
        if (same_function) out.emplace(pc, SourceLine{std::move(loc.file), loc.line});
    }
    return out;
}

ScopeLines scope_lines(const hil::ProfileScope& scope, const hil::FunctionMap& map, const AddressLines& lines) {
    ScopeLines out;
    std::map<std::pair<std::string, uint32_t>, LineCycles> by_line;
    for (std::size_t word = 0; word < scope.word_cycles.size(); ++word) {
        const hil::Cycles cycles = scope.word_cycles[word];
        if (cycles == 0) continue;
        const auto address = static_cast<uint32_t>(word * 2);
        const hil::FunctionId function = map.at(address);
        const auto line = lines.find(address);
        if (line == lines.end()) {
            out.unlined.push_back(UnlinedCycles{address, function, cycles});
            out.unlined_cycles += cycles;
            continue;
        }
        LineCycles& l = by_line[{line->second.file, line->second.line}];
        l.where = line->second;
        l.self_cycles += cycles;
        // Words come in address order: a function's words are contiguous.
        if (l.functions.empty() || l.functions.back() != function) l.functions.push_back(function);
        out.line_cycles += cycles;
    }
    for (auto& [key, l] : by_line) {
        std::sort(l.functions.begin(), l.functions.end());
        l.functions.erase(std::unique(l.functions.begin(), l.functions.end()), l.functions.end());
        out.lines.push_back(std::move(l));
    }
    // by_line is in (file, line) order and the sorts are stable: ties stay in it.
    std::stable_sort(out.lines.begin(), out.lines.end(),
                     [](const LineCycles& a, const LineCycles& b) { return a.self_cycles > b.self_cycles; });
    std::stable_sort(out.unlined.begin(), out.unlined.end(),
                     [](const UnlinedCycles& a, const UnlinedCycles& b) { return a.self_cycles > b.self_cycles; });
    return out;
}

std::string unlined_label(const hil::FunctionMap& map, uint32_t address) {
    const hil::FunctionInfo& f = map.function(map.at(address));
    return fmt::format("(no line info) {}+0x{:x}", f.name, address - f.address);
}

}  // namespace ddmr::tools
