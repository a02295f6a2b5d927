// callgrind.out from a FunctionProfiler (format: see the header).
#include "callgrind_output.hpp"

#include <fmt/format.h>

#include <map>
#include <vector>

namespace ddmr::tools {
namespace {

constexpr const char* kUnknownFile = "???";

struct CallCost {
    std::string callee_file;
    std::string callee_name;
    uint32_t callee_line = 0;
    uint32_t site_line = 0;
    uint64_t calls = 0;
    hil::Cycles inclusive_cycles = 0;
};

/// What one function writes, by file: its self cycles per line and its call sites.
struct FileCosts {
    std::map<uint32_t, hil::Cycles> self;
    std::vector<CallCost> calls;
};

}  // namespace

std::string callgrind_scope(const hil::FunctionProfiler& profiler) {
    return profiler.control_loop().iterations > 0 ? "control_loop" : "whole_run";
}

std::string callgrind_profile(const hil::FunctionProfiler& p, const FunctionProfileContext& c,
                              const std::string& command) {
    const bool loop = callgrind_scope(p) == "control_loop";
    const hil::ProfileScope s = loop ? p.control_loop() : p.whole_run();
    const hil::FunctionMap& map = p.map();
    const std::size_t n = map.size();

    // Unique names, files and first lines of the functions.
    std::vector<std::string> names(n);
    std::map<std::string, int> name_uses;
    for (std::size_t id = 0; id < n; ++id) {
        names[id] = hil::demangle(map.function(static_cast<hil::FunctionId>(id)).name);
        ++name_uses[names[id]];
    }
    std::vector<std::string> files(n, kUnknownFile);
    std::vector<uint32_t> first_lines(n, 0);
    for (std::size_t id = 0; id < n; ++id) {
        const hil::FunctionInfo& f = map.function(static_cast<hil::FunctionId>(id));
        if (name_uses[names[id]] > 1) names[id] += fmt::format(" @0x{:x}", f.address);
        const auto line = c.lines.lower_bound(f.address);
        if (line != c.lines.end() && line->first < f.end) {
            files[id] = line->second.file;
            if (line->first == f.address) first_lines[id] = line->second.line;
        }
    }

    std::vector<std::map<std::string, FileCosts>> costs(n);
    // (file, line) of an address in `function`: line 0 of its file without a line.
    const auto position = [&](hil::FunctionId function, uint32_t address) {
        const auto line = c.lines.find(address);
        return line == c.lines.end() ? std::make_pair(files[function], 0U)
                                     : std::make_pair(line->second.file, line->second.line);
    };
    for (std::size_t word = 0; word < s.word_cycles.size(); ++word) {
        if (s.word_cycles[word] == 0) continue;
        const auto address = static_cast<uint32_t>(word * 2);
        const hil::FunctionId id = map.at(address);
        const auto [file, line] = position(id, address);
        costs[id][file].self[line] += s.word_cycles[word];
    }
    for (std::size_t i = 0; i < s.edges.size(); ++i) {
        const hil::CallEdge& e = p.edges()[i];
        const hil::EdgeCounts& counts = s.edges[i];
        if (e.caller == hil::CallEdge::kNoCaller || counts.calls == 0) continue;
        const auto [file, line] = position(e.caller, e.site);
        costs[e.caller][file].calls.push_back(CallCost{files[e.callee], names[e.callee], first_lines[e.callee], line,
                                                       counts.calls, counts.inclusive_cycles});
    }

    std::string out = "# callgrind format\nversion: 1\ncreator: ddmr-hil\n";
    out += fmt::format("cmd: {}\n", command);
    out += loop ? fmt::format("desc: Scope: control_loop: {} completed control-loop iterations, from one return of "
                              "{}() to the next\n",
                              s.iterations, c.loop_mark)
                : "desc: Scope: whole_run: every instruction from reset to the end of the run\n";
    out += fmt::format("desc: Clock: {} Hz; interrupts are their handlers' cost, not the interrupted code's\n",
                       c.clock_hz);
    out += "positions: line\nevent: Cycles : AVR clock cycles\nevents: Cycles\n";
    for (std::size_t id = 0; id < n; ++id) {
        if (costs[id].empty()) continue;
        const std::string& home = files[id];
        out += fmt::format("\nfl={}\nfn={}\n", home, names[id]);
        // The function's own file first, then the files of inlined code.
        std::vector<const std::string*> order;
        if (costs[id].count(home) != 0) order.push_back(&home);
        for (const auto& [file, fc] : costs[id]) {
            if (file != home) order.push_back(&file);
        }
        std::string current = home;
        for (const std::string* file : order) {
            if (*file != current) out += fmt::format("{}={}\n", *file == home ? "fe" : "fi", *file);
            current = *file;
            const FileCosts& fc = costs[id].at(*file);
            for (const auto& [line, cycles] : fc.self) out += fmt::format("{} {}\n", line, cycles);
            for (const CallCost& call : fc.calls) {
                out += fmt::format("cfi={}\ncfn={}\ncalls={} {}\n{} {}\n", call.callee_file, call.callee_name,
                                   call.calls, call.callee_line, call.site_line, call.inclusive_cycles);
            }
        }
    }
    return out;
}

}  // namespace ddmr::tools
