// profile.json / profile.txt / the stdout table from a FunctionProfiler.
#include "function_profile_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <memory>
#include <vector>

namespace ddmr::tools {
namespace {

using nlohmann::json;

using hil::demangle;

struct ScopeView {
    const char* key;
    const char* title;
    std::string description;
    hil::ProfileScope scope;
    bool control_loop;
};

std::vector<ScopeView> scopes(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    return {
        {"whole_run", "Whole run", "every instruction from reset to the end of the run", p.whole_run(), false},
        {"control_loop", "Control loop",
         "completed control-loop iterations: from one return of " + c.loop_mark +
             "() to the next, from the first return after the case byte was sent",
         p.control_loop(), true},
    };
}

/// Functions that ran in `scope`, by self cycles (largest first), ties by address.
std::vector<hil::FunctionId> ranked(const hil::FunctionProfiler& p, const hil::ProfileScope& scope) {
    std::vector<hil::FunctionId> ids;
    for (std::size_t id = 0; id < scope.functions.size(); ++id) {
        const auto& f = scope.functions[id];
        if (f.calls > 0 || f.inclusive_cycles > 0 || f.self_cycles > 0) ids.push_back(static_cast<hil::FunctionId>(id));
    }
    std::stable_sort(ids.begin(), ids.end(), [&](hil::FunctionId a, hil::FunctionId b) {
        const auto sa = scope.functions[a].self_cycles;
        const auto sb = scope.functions[b].self_cycles;
        if (sa != sb) return sa > sb;
        return p.map().function(a).address < p.map().function(b).address;
    });
    return ids;
}

double share(hil::Cycles part, hil::Cycles whole) {
    return whole == 0 ? 0.0 : static_cast<double>(part) / static_cast<double>(whole);
}

double to_us(hil::Cycles cycles, uint32_t clock_hz) {
    return hil::cycles_to_s(cycles, clock_hz) * 1e6;
}

std::string table(const hil::FunctionProfiler& p, const ScopeView& v, const FunctionProfileContext& c,
                  std::size_t limit) {
    constexpr std::size_t kNameWidth = 44;
    const hil::ProfileScope& s = v.scope;
    std::string out = fmt::format("{}: {} cycles ({:.3f} s), {:.1f} % in interrupts", v.title, s.cycles,
                                  hil::cycles_to_s(s.cycles, c.clock_hz), 100.0 * share(s.interrupt_cycles, s.cycles));
    if (v.control_loop) {
        out += fmt::format(", {} iterations", s.iterations);
        if (s.iterations > 0) {
            out += fmt::format(" of {:.1f} us on average",
                               to_us(s.cycles, c.clock_hz) / static_cast<double>(s.iterations));
        }
    }
    out += fmt::format("\n  ({})\n", v.description);
    out += fmt::format("{:>4}  {:<{}} {:>8} {:>8} {:>12} {:>7} {:>12} {:>7} {:>12}\n", "#", "function", kNameWidth,
                       "address", "calls", "self_cyc", "self%", "incl_cyc", "incl%", "self_us");
    const auto ids = ranked(p, s);
    for (std::size_t i = 0; i < ids.size() && i < limit; ++i) {
        const auto& info = p.map().function(ids[i]);
        const auto& f = s.functions[ids[i]];
        std::string name = demangle(info.name);
        if (name.size() > kNameWidth) {
            name.resize(kNameWidth - 3);
            name += "...";
        }
        out += fmt::format("{:>4}  {:<{}} {:>#8x} {:>8} {:>12} {:>6.2f}% {:>12} {:>6.2f}% {:>12.1f}\n", i + 1, name,
                           kNameWidth, info.address, f.calls, f.self_cycles, 100.0 * share(f.self_cycles, s.cycles),
                           f.inclusive_cycles, 100.0 * share(f.inclusive_cycles, s.cycles),
                           to_us(f.self_cycles, c.clock_hz));
    }
    return out;
}

}  // namespace

json function_profile_json(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    json out;
    out["clock_hz"] = c.clock_hz;
    out["sorted_by"] = "self_cycles descending, then address";
    out["stack"] = {{"max_depth", hil::FunctionProfiler::kDefaultMaxDepth},
                    {"max_depth_seen", p.max_depth_seen()},
                    {"overflows", p.stack_overflows()},
                    {"mid_function_branches", p.mid_function_branches()}};
    for (const ScopeView& v : scopes(p, c)) {
        const hil::ProfileScope& s = v.scope;
        json functions = json::array();
        for (const hil::FunctionId id : ranked(p, s)) {
            const auto& info = p.map().function(id);
            const auto& f = s.functions[id];
            json row = {{"name", info.name},
                        {"demangled", demangle(info.name)},
                        {"aliases", info.aliases},
                        {"address", info.address},
                        {"calls", f.calls},
                        {"self_cycles", f.self_cycles},
                        {"self_share", share(f.self_cycles, s.cycles)},
                        {"inclusive_cycles", f.inclusive_cycles},
                        {"inclusive_share", share(f.inclusive_cycles, s.cycles)},
                        {"self_us", to_us(f.self_cycles, c.clock_hz)}};
            functions.push_back(std::move(row));
        }
        json scope = {{"description", v.description},
                      {"cycles", s.cycles},
                      {"interrupt_cycles", s.interrupt_cycles},
                      {"functions", std::move(functions)}};
        if (v.control_loop) {
            scope["iterations"] = s.iterations;
            scope["loop_mark"] = c.loop_mark;
        }
        out["scopes"][v.key] = std::move(scope);
    }
    return out;
}

std::string function_profile_text(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    std::string out =
        "Flat profile: cycles per function from every executed instruction (ddmr-hil --profile).\n"
        "self = the function's own instructions; incl = with its callees, interrupts excluded;\n"
        "calls = calls, tail jumps and interrupt entries. Sorted by self cycles.\n\n";
    for (const ScopeView& v : scopes(p, c)) out += table(p, v, c, std::numeric_limits<std::size_t>::max()) + "\n";
    return out;
}

std::string function_profile_top(const hil::FunctionProfiler& p, const FunctionProfileContext& c,
                                 std::size_t top_n) {
    std::string out;
    for (const ScopeView& v : scopes(p, c)) {
        out += fmt::format("Top {} by self cycles. ", top_n) + table(p, v, c, top_n);
    }
    return out;
}

}  // namespace ddmr::tools
