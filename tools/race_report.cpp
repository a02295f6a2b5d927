#include "race_report.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>

#include "common/source_lines.hpp"
#include "hil/data_objects.hpp"

namespace ddmr::tools {
namespace {

using nlohmann::json;

std::vector<std::string> vector_names(hil::VectorMask mask, const hil::McuDescription& mcu) {
    std::vector<std::string> out;
    for (int v = 1; v < mcu.vector_count(); ++v) {
        if ((mask & (hil::VectorMask{1} << static_cast<unsigned>(v))) != 0) out.push_back(mcu.vector_name(v));
    }
    return out;
}

std::string joined(const std::vector<std::string>& v) {
    if (v.empty()) return "-";
    std::string s;
    for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
}

hil::VectorMask split_vectors(const hil::SplitAccess& a) {
    hil::VectorMask m = 0;
    for (std::size_t v = 0; v < a.splits.size(); ++v) {
        if (a.splits[v] != 0) m |= hil::VectorMask{1} << v;
    }
    return m;
}

std::string hex(uint64_t v, uint16_t bytes) { return fmt::format("0x{:0{}x}", v, 2 * bytes); }

/// The races among the split accesses, in a stable order (variable address, kind, pc).
std::vector<const hil::SplitAccess*> races_of(const hil::RaceDetector& races) {
    std::vector<const hil::SplitAccess*> out;
    for (const auto& a : races.splits()) {
        if (races.is_race(a)) out.push_back(&a);
    }
    std::sort(out.begin(), out.end(), [&](const hil::SplitAccess* a, const hil::SplitAccess* b) {
        const auto ka = std::make_tuple(races.objects()[a->object].address, a->kind, a->pc);
        const auto kb = std::make_tuple(races.objects()[b->object].address, b->kind, b->pc);
        return ka < kb;
    });
    return out;
}

const char* kind_name(hil::AccessKind k) { return k == hil::AccessKind::kRead ? "read" : "write"; }

std::string register_name(uint8_t r) { return fmt::format("r{}", r); }

}  // namespace

std::string CodeNames::function(uint32_t pc) const {
    if (functions == nullptr) return "";
    return hil::demangle(functions->function(functions->at(pc)).name);
}

std::string CodeNames::line(uint32_t pc) const {
    const auto it = lines.find(pc);
    return it == lines.end() ? std::string() : it->second;
}

std::vector<uint32_t> race_report_pcs(const hil::RaceDetector& races) {
    std::vector<uint32_t> pcs;
    for (const auto& a : races.splits()) pcs.push_back(a.pc);
    for (const auto& s : races.stale_reads()) {
        pcs.push_back(s.where.load_pc);
        pcs.push_back(s.where.loop_begin);
    }
    return pcs;
}

std::map<std::size_t, MainSiteCounts> main_site_counts(const hil::RaceDetector& races,
                                                      const hil::FunctionMap& functions) {
    std::map<std::size_t, MainSiteCounts> counts;
    for (const auto& s : races.shared()) {
        counts[s.object] = MainSiteCounts{races.main_sites(s.object, false, functions).size(),
                                          races.main_sites(s.object, true, functions).size()};
    }
    return counts;
}

json races_json(const hil::RaceDetector& races, const CodeNames& names) {
    const auto& objects = races.objects();
    json shared = json::array();
    for (const auto& s : races.shared()) {
        const auto& o = objects[s.object];
        json v = {{"variable", o.name}, {"address", o.address}, {"size", o.size},
                  {"isr_writers", vector_names(s.isr_writers, races.mcu())},
                  {"isr_readers", vector_names(s.isr_readers, races.mcu())}};
        if (const auto it = names.main_sites.find(s.object); it != names.main_sites.end()) {
            v["main_loads"] = it->second.loads;
            v["main_stores"] = it->second.stores;
        }
        shared.push_back(v);
    }
    const auto source_or_null = [&](uint32_t pc) {
        const std::string l = names.line(pc);
        return l.empty() ? json(nullptr) : json(l);
    };
    json torn = json::array();
    for (const hil::SplitAccess* a : races_of(races)) {
        const auto& o = objects[a->object];
        json example = nullptr;
        if (a->observed > 0) {
            example = a->kind == hil::AccessKind::kRead
                          ? json{{"before", hex(a->example_before, o.size)}, {"read", hex(a->example_seen, o.size)},
                                 {"after", hex(a->example_after, o.size)}}
                          : json{{"isr_read", hex(a->example_seen, o.size)},
                                 {"being_written", hex(a->example_after, o.size)}};
        }
        torn.push_back({{"variable", o.name},
                        {"size", o.size},
                        {"access", kind_name(a->kind)},
                        {"status", a->observed > 0 ? "observed" : "possible"},
                        {"function", names.function(a->pc)},
                        {"pc", a->pc},
                        {"pc_hex", fmt::format("0x{:04x}", a->pc)},
                        {"source", source_or_null(a->pc)},
                        {"split_by", vector_names(split_vectors(*a), races.mcu())},
                        {"splits", races.race_splits(*a)},
                        {"torn", a->torn},
                        {"observed", a->observed},
                        {"first_cycle", a->first_cycle},
                        {"example", example}});
    }
    json stale = json::array();
    for (const auto& s : races.stale_reads()) {
        const auto& o = objects[s.where.object];
        stale.push_back({{"variable", o.name},
                         {"size", o.size},
                         {"function", names.function(s.where.loop_begin)},
                         {"load_pc", s.where.load_pc},
                         {"load_source", source_or_null(s.where.load_pc)},
                         {"register", register_name(s.where.reg)},
                         {"loop_begin_pc", s.where.loop_begin},
                         {"loop_end_pc", s.where.loop_end},
                         {"loop_source", source_or_null(s.where.loop_begin)},
                         {"writes_missed", s.writes_missed},
                         {"writers", vector_names(s.vectors, races.mcu())},
                         {"first_cycle", s.first_cycle}});
    }
    uint64_t observed = 0;
    uint64_t possible = 0;
    for (const auto& t : torn) (t["status"] == "observed" ? observed : possible) += 1;
    return json{{"entries_checked", races.stats().entries_checked},
                {"dropped", races.stats().dropped},
                {"torn_observed", observed},
                {"torn_possible", possible},
                {"stale_reads", stale.size()},
                {"shared_variables", shared},
                {"torn", torn},
                {"stale", stale}};
}

json torn_reads_summary(const hil::RaceDetector& races) {
    json out = json::object();
    for (const auto& s : races.shared()) {
        const auto& o = races.objects()[s.object];
        if (s.isr_writers == 0 || o.size < 2 || o.size > hil::RaceDetector::kMaxVariableBytes) continue;
        uint64_t split = 0;
        uint64_t torn = 0;
        uint64_t visible = 0;
        for (const auto& a : races.splits()) {
            if (a.object != s.object || a.kind != hil::AccessKind::kRead) continue;
            split += races.race_splits(a);
            torn += a.torn;
            visible += a.observed;
        }
        out[o.name] = {{"split_reads", split}, {"torn", torn}, {"visible", visible}};
    }
    return out;
}

std::string races_markdown(const hil::RaceDetector& races, const CodeNames& names) {
    const auto& objects = races.objects();
    std::string md = "\n## Shared variables and races\n\n";
    const auto shared = races.shared();
    md += "Variables an ISR loaded or stored (every ISR instruction decoded), with the main program's direct "
          "loads (LDS) and stores (STS) of them:\n\n";
    if (shared.empty()) {
        md += "None: no ISR accessed a variable in SRAM.\n";
    } else {
        md += "| variable | bytes | written by | read by | main LDS / STS |\n|---|---:|---|---|---:|\n";
        for (const auto& s : shared) {
            const auto& o = objects[s.object];
            std::string sites = "-";
            if (const auto it = names.main_sites.find(s.object); it != names.main_sites.end()) {
                sites = fmt::format("{} / {}", it->second.loads, it->second.stores);
            }
            md += fmt::format("| `{}` | {} | {} | {} | {} |\n", o.name, o.size,
                              joined(vector_names(s.isr_writers, races.mcu())),
                              joined(vector_names(s.isr_readers, races.mcu())), sites);
        }
    }
    md += "\n### Torn accesses\n\n";
    const auto torn = races_of(races);
    if (torn.empty()) {
        md += fmt::format("None: no multi-byte access of the main program to an ISR-shared variable was split by "
                          "an ISR that shares it ({} interrupt entries from the main program checked).\n",
                          races.stats().entries_checked);
    } else {
        md += "A read split by an ISR that writes the variable, or a write split by an ISR that reads it. "
              "*observed*: a torn value was seen (a read returned a value the variable never held; an ISR read "
              "a value other than the one being written); *possible*: split, but no torn value seen.\n\n";
        md += "| variable | bytes | access | function | pc | source | split by | splits | torn | status |\n"
              "|---|---:|---|---|---:|---|---|---:|---:|---|\n";
        for (const hil::SplitAccess* a : torn) {
            const auto& o = objects[a->object];
            const std::string line = names.line(a->pc);
            md += fmt::format("| `{}` | {} | {} | `{}` | 0x{:04x} | {} | {} | {} | {} | {} |\n", o.name, o.size,
                              kind_name(a->kind), names.function(a->pc), a->pc, line.empty() ? "-" : line,
                              joined(vector_names(split_vectors(*a), races.mcu())), races.race_splits(*a), a->torn,
                              a->observed > 0 ? fmt::format("observed ({}x)", a->observed) : "possible");
        }
        for (const hil::SplitAccess* a : torn) {
            if (a->observed == 0) continue;
            const auto& o = objects[a->object];
            if (a->kind == hil::AccessKind::kRead) {
                md += fmt::format("\n`{}` at 0x{:04x}: first observed read {} (the variable went from {} to {}).\n",
                                  o.name, a->pc, hex(a->example_seen, o.size), hex(a->example_before, o.size),
                                  hex(a->example_after, o.size));
            } else {
                md += fmt::format("\n`{}` at 0x{:04x}: the ISR first read {} while {} was being written.\n", o.name,
                                  a->pc, hex(a->example_seen, o.size), hex(a->example_after, o.size));
            }
        }
    }
    md += "\n### Stale reads\n\n";
    if (races.stale_reads().empty()) {
        md += "None: the main program never spun in a register-only loop on a variable an ISR wrote meanwhile.\n";
    } else {
        md += "The main program spins in a loop that reads no memory, on a register loaded from the variable before "
              "the loop, while an ISR writes the variable: the loop cannot see the change. Declare the variable "
              "`volatile`.\n\n";
        md += "| variable | bytes | function | loaded at | loop | register | ISR writes missed | written by |\n"
              "|---|---:|---|---|---|---|---:|---|\n";
        for (const auto& s : races.stale_reads()) {
            const auto& o = objects[s.where.object];
            const auto where = [&](uint32_t pc) {
                const std::string l = names.line(pc);
                return l.empty() ? fmt::format("0x{:04x}", pc) : fmt::format("0x{:04x} ({})", pc, l);
            };
            md += fmt::format("| `{}` | {} | `{}` | {} | {}..0x{:04x} | {} | {} | {} |\n", o.name, o.size,
                              names.function(s.where.loop_begin), where(s.where.load_pc), where(s.where.loop_begin),
                              s.where.loop_end, register_name(s.where.reg), s.writes_missed,
                              joined(vector_names(s.vectors, races.mcu())));
        }
    }
    return md;
}

RaceReport race_report(const hil::RaceDetector& races, const hil::ElfImage& elf) {
    const hil::FunctionMap code_map(elf, races.mcu());
    CodeNames names{&code_map, {}, main_site_counts(races, code_map)};
    try {
        names.lines = source_lines(elf.path(), race_report_pcs(races));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "ddmr-hil: warning: no source lines in the race report: %s\n", e.what());
    }
    return RaceReport{races_json(races, names), races_markdown(races, names)};
}

uint64_t observed_torn(const hil::RaceDetector& races, const std::vector<std::string>& variables) {
    uint64_t n = 0;
    for (const auto& a : races.splits()) {
        if (!races.is_race(a)) continue;
        const std::string& name = races.objects()[a.object].name;
        if (!variables.empty() && std::find(variables.begin(), variables.end(), name) == variables.end()) continue;
        n += a.observed;
    }
    return n;
}

}  // namespace ddmr::tools
