#include "fast_forward_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <set>
#include <utility>
#include <vector>
#include <string>

#include "hil/avr_core.hpp"

namespace ddmr::tools {
namespace {

/// At most this many refused loops are listed, those visited most first.
constexpr std::size_t kMaxRefused = 10;

std::string hex(uint32_t pc) { return fmt::format("0x{:04x}", pc); }

std::string function_of(const hil::AvrCore& core, uint32_t pc) {
    const auto f = core.elf().function_at(pc);
    return f ? f->name : std::string("?");
}

/// The functions a pass runs through, each once, in the order it enters them.
std::vector<std::string> functions_on(const hil::AvrCore& core, const std::vector<uint32_t>& path) {
    std::vector<std::string> out;
    for (uint32_t pc : path) {
        const std::string f = function_of(core, pc);
        if (std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    }
    return out;
}

}  // namespace

nlohmann::json fast_forward_json(const hil::AvrCore& core, hil::Cycles cycles_total) {
    const hil::FastForward* ff = core.fast_forward();
    if (ff == nullptr) return {{"enabled", false}};
    const hil::FastForwardStats s = ff->stats();
    // One entry per loop: the anchors learned on one pass (the same PC range) merged.
    std::map<std::pair<uint32_t, uint32_t>, hil::SkippedLoop> merged;
    std::map<std::pair<uint32_t, uint32_t>, std::size_t> anchors;
    for (const hil::SkippedLoop& l : s.loops) {
        const auto key = std::make_pair(l.pc_low, l.pc_high);
        auto [it, fresh] = merged.try_emplace(key, l);
        ++anchors[key];
        if (fresh) continue;
        it->second.skips += l.skips;
        it->second.mismatches += l.mismatches;
        it->second.taken_back += l.taken_back;
        it->second.cycles_skipped += l.cycles_skipped;
    }
    nlohmann::json loops = nlohmann::json::array();
    for (const auto& [key, l] : merged) {
        loops.push_back({{"pc_range", {hex(l.pc_low), hex(l.pc_high)}},
                         {"functions", functions_on(core, l.path)},
                         {"pass_cycles", l.pass_cycles},
                         {"anchors", anchors[key]},
                         {"skips", l.skips},
                         {"cycles_skipped", l.cycles_skipped},
                         {"mismatches", l.mismatches},
                         {"taken_back", l.taken_back}});
    }
    // A refused anchor on a loop skipped from another anchor is no news.
    std::set<uint32_t> skipped_pcs;
    for (const hil::SkippedLoop& l : s.loops) skipped_pcs.insert(l.path.begin(), l.path.end());
    nlohmann::json refused = nlohmann::json::array();
    for (const hil::RefusedLoop& r : s.refused) {
        if (refused.size() == kMaxRefused) break;
        if (skipped_pcs.count(r.anchor) != 0) continue;
        refused.push_back({{"anchor", hex(r.anchor)},
                           {"function", function_of(core, r.anchor)},
                           {"reason", r.reason},
                           {"visits", r.visits}});
    }
    return {{"enabled", true},
            {"cycles_skipped", s.cycles_skipped},
            {"skipped_share", cycles_total > 0 ? static_cast<double>(s.cycles_skipped) / static_cast<double>(cycles_total)
                                               : 0.0},
            {"skips", s.skips},
            {"mismatches", s.mismatches},
            {"taken_back", s.taken_back},
            {"loops", loops},
            {"not_skipped", refused}};
}

}  // namespace ddmr::tools
