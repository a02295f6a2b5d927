// profile.json / profile.txt / the stdout table from a FunctionProfiler.
#include "function_profile_output.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <utility>
#include <vector>

namespace ddmr::tools {
namespace {

using nlohmann::json;

using hil::demangle;

constexpr const char* kSpontaneous = "<spontaneous>";

struct ScopeView {
    const char* key;
    const char* title;
    std::string description;
    hil::ProfileScope scope;
    bool control_loop;
    bool self_only = false;  ///< compute: self cycles only (no calls, inclusive cycles or call graph)
};

std::vector<ScopeView> scopes(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    std::vector<ScopeView> v = {
        {"whole_run", "Whole run", "every instruction from reset to the end of the run", p.whole_run(), false},
        {"control_loop", "Control loop",
         "completed control-loop iterations: from one return of " + c.loop_mark +
             "() to the next, from the first return after the case byte was sent",
         p.control_loop(), true},
    };
    if (p.has_wait_function()) {
        v.push_back({"compute", "Compute",
                     "the control loop without its wait: the same iterations, only while " + c.loop_mark +
                         "() is not running (from its return to its next call; interrupts then included); "
                         "self cycles only",
                     p.compute(), true, true});
    }
    return v;
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

/// The raw symbol name, or <spontaneous>.
std::string edge_end_name(const hil::FunctionProfiler& p, hil::FunctionId id) {
    return id == hil::CallEdge::kNoCaller ? std::string(kSpontaneous) : p.map().function(id).name;
}

/// The heading line of a scope's table: its cycles, interrupts, iterations.
std::string scope_heading(const ScopeView& v, const FunctionProfileContext& c) {
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
    return out;
}

/// gprof's call graph: functions by inclusive cycles, each with its callers
/// (above) and callees (below); an edge row gives the edge's inclusive cycles
/// and its calls out of all the calls of the callee.
std::string call_graph_text(const hil::FunctionProfiler& p, const ScopeView& v, const FunctionProfileContext& c) {
    const hil::ProfileScope& s = v.scope;
    const auto edges = function_edges(p, s);
    std::vector<hil::FunctionId> ids = ranked(p, s);
    std::stable_sort(ids.begin(), ids.end(), [&](hil::FunctionId a, hil::FunctionId b) {
        const auto ia = s.functions[a].inclusive_cycles;
        const auto ib = s.functions[b].inclusive_cycles;
        if (ia != ib) return ia > ib;
        return p.map().function(a).address < p.map().function(b).address;
    });
    std::map<hil::FunctionId, std::size_t> index;
    for (std::size_t i = 0; i < ids.size(); ++i) index[ids[i]] = i + 1;
    const auto label = [&](hil::FunctionId id) {
        if (id == hil::CallEdge::kNoCaller) return std::string(kSpontaneous);
        return fmt::format("{} [{}]", demangle(p.map().function(id).name), index[id]);
    };
    std::string out = fmt::format("Call graph. {}\n", scope_heading(v, c));
    out += fmt::format("{:<7} {:>7} {:>12} {:>12} {:>19}  {}\n", "index", "incl%", "self_cyc", "incl_cyc", "calls",
                       "name");
    for (const hil::FunctionId id : ids) {
        const auto& f = s.functions[id];
        for (const FunctionEdge& e : edges) {
            if (e.callee != id) continue;
            out += fmt::format("{:<7} {:>7} {:>12} {:>12} {:>19}      {}\n", "", "", "", e.inclusive_cycles,
                               fmt::format("{}/{}", e.calls, f.calls), label(e.caller));
        }
        out += fmt::format("{:<7} {:>6.2f}% {:>12} {:>12} {:>19}  {}\n", fmt::format("[{}]", index[id]),
                           100.0 * share(f.inclusive_cycles, s.cycles), f.self_cycles, f.inclusive_cycles, f.calls,
                           label(id));
        for (const FunctionEdge& e : edges) {
            if (e.caller != id) continue;
            out += fmt::format("{:<7} {:>7} {:>12} {:>12} {:>19}      {}\n", "", "", "", e.inclusive_cycles,
                               fmt::format("{}/{}", e.calls, s.functions[e.callee].calls), label(e.callee));
        }
        out += "\n";
    }
    return out;
}

/// A scope's top `limit` source lines and instructions without a line, merged
/// by self cycles (lines first on ties).
std::string lines_text(const hil::FunctionProfiler& p, const ScopeView& v, const FunctionProfileContext& c,
                       std::size_t limit) {
    const hil::ProfileScope& s = v.scope;
    const ScopeLines sl = scope_lines(s, p.map(), c.lines);
    std::string out = fmt::format("{}\n  {} source lines, {} instructions without line info: {} cycles ({:.2f} %)\n",
                                  scope_heading(v, c), sl.lines.size(), sl.unlined.size(), sl.unlined_cycles,
                                  100.0 * share(sl.unlined_cycles, s.cycles));
    if (!c.lines_error.empty()) out += fmt::format("  (no source lines: {})\n", c.lines_error);
    out += fmt::format("{:>4}  {:>12} {:>7}  {}\n", "#", "self_cyc", "self%", "line (function)");
    std::size_t li = 0;
    std::size_t ui = 0;
    for (std::size_t rank = 1; rank <= limit && (li < sl.lines.size() || ui < sl.unlined.size()); ++rank) {
        const bool line = ui == sl.unlined.size() ||
                          (li < sl.lines.size() && sl.lines[li].self_cycles >= sl.unlined[ui].self_cycles);
        hil::Cycles cycles = 0;
        std::string where;
        if (line) {
            const LineCycles& l = sl.lines[li++];
            cycles = l.self_cycles;
            std::string functions;
            for (const hil::FunctionId id : l.functions) {
                functions += (functions.empty() ? "" : ", ") + demangle(p.map().function(id).name);
            }
            where = fmt::format("{}:{} ({})", l.where.file, l.where.line, functions);
        } else {
            const UnlinedCycles& u = sl.unlined[ui++];
            cycles = u.self_cycles;
            where = unlined_label(p.map(), u.address);
        }
        out += fmt::format("{:>4}  {:>12} {:>6.2f}%  {}\n", rank, cycles, 100.0 * share(cycles, s.cycles), where);
    }
    return out;
}

json call_graph_json(const hil::FunctionProfiler& p, const hil::ProfileScope& s) {
    json rows = json::array();
    for (const FunctionEdge& e : function_edges(p, s)) {
        json row = {{"caller", edge_end_name(p, e.caller)},
                    {"caller_address", nullptr},
                    {"callee", edge_end_name(p, e.callee)},
                    {"callee_address", p.map().function(e.callee).address},
                    {"calls", e.calls},
                    {"inclusive_cycles", e.inclusive_cycles},
                    {"inclusive_share", share(e.inclusive_cycles, s.cycles)}};
        if (e.caller != hil::CallEdge::kNoCaller) row["caller_address"] = p.map().function(e.caller).address;
        rows.push_back(std::move(row));
    }
    return rows;
}

json source_lines_json(const hil::FunctionProfiler& p, const hil::ProfileScope& s, const AddressLines& lines) {
    const ScopeLines sl = scope_lines(s, p.map(), lines);
    json line_rows = json::array();
    for (const LineCycles& l : sl.lines) {
        json functions = json::array();
        for (const hil::FunctionId id : l.functions) functions.push_back(p.map().function(id).name);
        line_rows.push_back({{"file", l.where.file},
                             {"line", l.where.line},
                             {"self_cycles", l.self_cycles},
                             {"self_share", share(l.self_cycles, s.cycles)},
                             {"functions", std::move(functions)}});
    }
    json unlined_rows = json::array();
    for (const UnlinedCycles& u : sl.unlined) {
        const auto& f = p.map().function(u.function);
        unlined_rows.push_back({{"address", u.address},
                                {"function", f.name},
                                {"offset", u.address - f.address},
                                {"label", unlined_label(p.map(), u.address)},
                                {"self_cycles", u.self_cycles},
                                {"self_share", share(u.self_cycles, s.cycles)}});
    }
    return {{"line_cycles", sl.line_cycles},
            {"no_line_info_cycles", sl.unlined_cycles},
            {"no_line_info_share", share(sl.unlined_cycles, s.cycles)},
            {"lines", std::move(line_rows)},
            {"no_line_info", std::move(unlined_rows)}};
}

std::string table(const hil::FunctionProfiler& p, const ScopeView& v, const FunctionProfileContext& c,
                  std::size_t limit) {
    constexpr std::size_t kNameWidth = 44;
    const hil::ProfileScope& s = v.scope;
    std::string out = scope_heading(v, c) + fmt::format("\n  ({})\n", v.description);
    if (v.self_only) {
        out += fmt::format("{:>4}  {:<{}} {:>8} {:>12} {:>7} {:>12}\n", "#", "function", kNameWidth, "address",
                           "self_cyc", "self%", "self_us");
    } else {
        out += fmt::format("{:>4}  {:<{}} {:>8} {:>8} {:>12} {:>7} {:>12} {:>7} {:>12}\n", "#", "function",
                           kNameWidth, "address", "calls", "self_cyc", "self%", "incl_cyc", "incl%", "self_us");
    }
    const auto ids = ranked(p, s);
    for (std::size_t i = 0; i < ids.size() && i < limit; ++i) {
        const auto& info = p.map().function(ids[i]);
        const auto& f = s.functions[ids[i]];
        std::string name = demangle(info.name);
        if (name.size() > kNameWidth) {
            name.resize(kNameWidth - 3);
            name += "...";
        }
        if (v.self_only) {
            out += fmt::format("{:>4}  {:<{}} {:>#8x} {:>12} {:>6.2f}% {:>12.1f}\n", i + 1, name, kNameWidth,
                               info.address, f.self_cycles, 100.0 * share(f.self_cycles, s.cycles),
                               to_us(f.self_cycles, c.clock_hz));
            continue;
        }
        out += fmt::format("{:>4}  {:<{}} {:>#8x} {:>8} {:>12} {:>6.2f}% {:>12} {:>6.2f}% {:>12.1f}\n", i + 1, name,
                           kNameWidth, info.address, f.calls, f.self_cycles, 100.0 * share(f.self_cycles, s.cycles),
                           f.inclusive_cycles, 100.0 * share(f.inclusive_cycles, s.cycles),
                           to_us(f.self_cycles, c.clock_hz));
    }
    return out;
}

}  // namespace

std::vector<FunctionEdge> function_edges(const hil::FunctionProfiler& p, const hil::ProfileScope& scope) {
    // Keyed by (caller address order, callee address order): <spontaneous> first.
    std::map<std::pair<int, int>, FunctionEdge> by_pair;
    for (std::size_t i = 0; i < scope.edges.size(); ++i) {
        const hil::EdgeCounts& counts = scope.edges[i];
        if (counts.calls == 0 && counts.inclusive_cycles == 0) continue;
        const hil::CallEdge& e = p.edges()[i];
        const int caller_key = e.caller == hil::CallEdge::kNoCaller ? -1 : e.caller;
        FunctionEdge& f = by_pair[{caller_key, e.callee}];
        f.caller = e.caller;
        f.callee = e.callee;
        f.calls += counts.calls;
        f.inclusive_cycles += counts.inclusive_cycles;
    }
    std::vector<FunctionEdge> out;
    out.reserve(by_pair.size());
    for (const auto& [key, e] : by_pair) out.push_back(e);
    std::stable_sort(out.begin(), out.end(), [](const FunctionEdge& a, const FunctionEdge& b) {
        return a.inclusive_cycles > b.inclusive_cycles;
    });
    return out;
}

json function_profile_json(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    json out;
    out["clock_hz"] = c.clock_hz;
    out["sorted_by"] = "self_cycles descending, then address";
    out["line_info"] = {{"source", "avr-addr2line (DWARF or stabs), checked against the symbol table"},
                        {"addresses_with_line", c.lines.size()},
                        {"error", c.lines_error.empty() ? json(nullptr) : json(c.lines_error)}};
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
                        {"self_cycles", f.self_cycles},
                        {"self_share", share(f.self_cycles, s.cycles)},
                        {"self_us", to_us(f.self_cycles, c.clock_hz)}};
            if (!v.self_only) {
                row["calls"] = f.calls;
                row["inclusive_cycles"] = f.inclusive_cycles;
                row["inclusive_share"] = share(f.inclusive_cycles, s.cycles);
            }
            functions.push_back(std::move(row));
        }
        json scope = {{"description", v.description},
                      {"cycles", s.cycles},
                      {"interrupt_cycles", s.interrupt_cycles},
                      {"functions", std::move(functions)},
                      {"source_lines", source_lines_json(p, s, c.lines)}};
        if (!v.self_only) scope["call_graph"] = call_graph_json(p, s);
        if (v.control_loop) {
            scope["iterations"] = s.iterations;
            scope["loop_mark"] = c.loop_mark;
        }
        out["scopes"][v.key] = std::move(scope);
    }
    return out;
}

std::string function_profile_text(const hil::FunctionProfiler& p, const FunctionProfileContext& c) {
    constexpr std::size_t kAll = std::numeric_limits<std::size_t>::max();
    constexpr std::size_t kTopLines = 50;
    const auto views = scopes(p, c);
    std::string out =
        "Flat profile: cycles per function from every executed instruction (ddmr-hil --profile).\n"
        "self = the function's own instructions; incl = with its callees, interrupts excluded;\n"
        "calls = calls, tail jumps and interrupt entries. Sorted by self cycles.\n\n";
    for (const ScopeView& v : views) out += table(p, v, c, kAll) + "\n";
    out += fmt::format(
        "Source lines: self cycles per source line (avr-addr2line), and per instruction where the\n"
        "ELF has no line (\"(no line info) function+offset\"), merged by self cycles; the top {}\n"
        "(all in profile.json).\n\n",
        kTopLines);
    for (const ScopeView& v : views) out += lines_text(p, v, c, kTopLines) + "\n";
    out +=
        "Call graph (gprof style): functions by inclusive cycles; above each, its callers, below it,\n"
        "its callees, with the inclusive cycles of those calls and their count out of the callee's\n"
        "calls. <spontaneous>: the reset and interrupt entries (no caller).\n\n";
    for (const ScopeView& v : views) {
        if (!v.self_only) out += call_graph_text(p, v, c);
    }
    return out;
}

std::string function_profile_top(const hil::FunctionProfiler& p, const FunctionProfileContext& c,
                                 std::size_t top_n) {
    std::string out;
    const auto views = scopes(p, c);
    for (const ScopeView& v : views) {
        out += fmt::format("Top {} by self cycles. ", top_n) + table(p, v, c, top_n);
    }
    // The lines a person can act on: the loop's own work (compute) when there is a loop.
    const ScopeView& lines = p.control_loop().iterations == 0 ? views[0] : views.back();
    out += fmt::format("Top {} source lines by self cycles. ", top_n) + lines_text(p, lines, c, top_n);
    return out;
}

}  // namespace ddmr::tools
