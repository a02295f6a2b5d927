#include "loop_mark.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>
#include <stdexcept>

#include "hil/avr_decode.hpp"

namespace ddmr::tools {
namespace {

namespace avr = hil::avr;

/// Marks that work in any Arduino sketch that has them: the core's main
/// calls serialEventRun() once per iteration (where Serial is linked), and
/// a paced loop calls delay() once.
constexpr const char* kUsualMarks[] = {"serialEventRun", "delay"};

struct Instruction {
    uint32_t pc = 0;  ///< flash byte address
    avr::Flow flow;
};

/// The instructions of a function, decoded from the ELF's .text.
std::vector<Instruction> decode(const hil::ElfImage& elf, const hil::ElfSymbol& function) {
    std::vector<Instruction> out;
    for (uint32_t pc = function.address; pc < function.address + function.size;) {
        const auto w0 = elf.text_word(pc);
        if (!w0) break;
        out.push_back({pc, avr::decode_flow(*w0, elf.text_word(pc + 2).value_or(0), pc)});
        pc += 2 * avr::instruction_words(*w0);
    }
    return out;
}

/// main's endless loop: from the target of its last backward JMP/RJMP to
/// that jump; the whole of main where it has none.
std::pair<uint32_t, uint32_t> loop_range(const hil::ElfSymbol& main, const std::vector<Instruction>& code) {
    for (auto it = code.rbegin(); it != code.rend(); ++it) {
        const avr::Flow& f = it->flow;
        if (f.kind == avr::Flow::Kind::kJump && f.target && *f.target >= main.address && *f.target <= it->pc) {
            return {*f.target, it->pc};
        }
    }
    return {main.address, main.address + main.size};
}

struct Candidates {
    std::vector<std::string> names;
    bool from_main = false;  ///< found in main's loop (else the usual marks present)
};

Candidates find_candidates(const hil::ElfImage& elf, std::size_t most) {
    Candidates c;
    const auto main = elf.find_functions("main");
    if (main.size() == 1) {
        c.from_main = true;
        const std::vector<Instruction> code = decode(elf, main.front());
        const auto [begin, end] = loop_range(main.front(), code);
        std::vector<uint32_t> order;  // call targets in the order of their first call
        std::map<uint32_t, int> sites;
        for (const Instruction& i : code) {
            if (i.pc < begin || i.pc > end || i.flow.kind != avr::Flow::Kind::kCall || !i.flow.target) continue;
            if (sites[*i.flow.target]++ == 0) order.push_back(*i.flow.target);
        }
        for (const uint32_t target : order) {
            const auto f = elf.function_at(target);
            // Called from two places, a function may run twice an iteration;
            // __mulsf3 and its kind are the compiler's, not the sketch's.
            if (sites[target] != 1 || !f || f->address != target || f->name.rfind("__", 0) == 0) continue;
            c.names.push_back(elf.function_name(*f));
        }
    } else {
        for (const char* usual : kUsualMarks) {
            if (elf.find_functions(usual).size() == 1) c.names.emplace_back(usual);
        }
    }
    // The usual marks first: they are once per iteration by construction.
    std::stable_partition(c.names.begin(), c.names.end(), [](const std::string& n) {
        return std::find(std::begin(kUsualMarks), std::end(kUsualMarks), n) != std::end(kUsualMarks);
    });
    if (c.names.size() > most) c.names.resize(most);
    return c;
}

/// "; try one that main's loop calls from one place: serialEventRun, delay"
/// (or why there is none), for the end of a one-line message; `except` (the
/// mark the message names) left out.
std::string suggestion(const hil::ElfImage& elf, const std::string& except = {}) {
    Candidates c = find_candidates(elf, 7);
    const bool any = !c.names.empty();
    c.names.erase(std::remove(c.names.begin(), c.names.end(), except), c.names.end());
    if (c.names.size() > 6) c.names.resize(6);
    if (c.names.empty() && any) return {};  // only `except`, which the message names
    if (c.names.empty()) {
        return c.from_main ? "; main's loop calls no function that could be the mark (each iteration must call one "
                             "that is not inlined)"
                           : "; the ELF has no main, nor delay or serialEventRun";
    }
    return fmt::format("; try one that {}: {}", c.from_main ? "main's loop calls from one place" : "the ELF has",
                       fmt::join(c.names, ", "));
}

}  // namespace

std::vector<std::string> loop_mark_candidates(const hil::ElfImage& elf, std::size_t most) {
    return find_candidates(elf, most).names;
}

hil::ElfSymbol resolve_loop_mark(const hil::ElfImage& elf, const std::string& name, const std::string& origin) {
    const std::vector<hil::ElfSymbol> found = elf.find_functions(name);
    const std::string firmware = elf.path().string();
    if (found.size() == 1) return found.front();
    if (found.size() > 1) {
        std::vector<std::string> names(found.size());
        std::transform(found.begin(), found.end(), names.begin(),
                       [](const hil::ElfSymbol& f) { return hil::demangle(f.name); });
        throw std::runtime_error(fmt::format("firmware {}: {} '{}' names {} functions: {}; give one of these names",
                                             firmware, origin, name, found.size(), fmt::join(names, ", ")));
    }
    const auto symbol = elf.find(name);
    const std::string what = !symbol                   ? "is no function in the ELF"
                             : symbol->is_object       ? "is a variable, not a function"
                                                       : "is no function with code";
    throw std::runtime_error(fmt::format("firmware {}: {} '{}' {}{}", firmware, origin, name, what, suggestion(elf)));
}

std::string default_loop_mark(const hil::ElfImage& elf) {
    if (elf.find_functions("loop").size() == 1) return "loop";
    const std::string firmware = elf.path().string();
    if (elf.find_functions("delay").size() == 1) {
        std::fprintf(stderr,
                     "ddmr-hil: loop() is not a function of %s (LTO inlined it into main): the loop mark falls back "
                     "to delay(), one call per iteration (--loop-mark names another%s)\n",
                     firmware.c_str(), suggestion(elf, "delay").c_str());
        return "delay";
    }
    throw std::runtime_error(fmt::format("firmware {}: neither loop() nor delay() is a function in the ELF (LTO "
                                         "inlined them): pass --loop-mark FUNCTION, a function each loop iteration "
                                         "calls once{}",
                                         firmware, suggestion(elf)));
}

}  // namespace ddmr::tools
