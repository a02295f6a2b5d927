#include "hil/zero_calls.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "hil/avr_decode.hpp"

namespace ddmr::hil {
namespace {

struct Instruction {
    uint32_t pc = 0;
    uint16_t w0 = 0;
    avr::Flow flow;
};

/// The instructions of [begin, end), decoded one after another.
std::vector<Instruction> decode_range(const ElfImage& elf, uint32_t begin, uint32_t end) {
    std::vector<Instruction> code;
    for (uint32_t pc = begin; pc + 2 <= end;) {
        const uint16_t w0 = elf.text_word_or_erased(pc);
        code.push_back({pc, w0, avr::decode_flow(w0, elf.text_word_or_erased(pc + 2), pc)});
        pc += 2 * avr::instruction_words(w0);
    }
    return code;
}

/// `ldi Rd, 0` (1110 0000 dddd 0000): the register d, else -1.
int ldi_zero_register(uint16_t w0) { return (w0 & 0xFF0F) == 0xE000 ? 16 + ((w0 >> 4) & 0x0F) : -1; }

/// True if the instructions just before code[branch] load 0 into a register
/// pair (a weak symbol's address, lo8 and hi8) that the branch's test reads.
bool tests_zero_address(const std::vector<Instruction>& code, std::size_t branch) {
    constexpr std::size_t kTestLength = 4;  // ldi, ldi, the test (or, cp/cpc, sbiw), the branch
    uint32_t zeroed = 0;  // bit n: Rn was loaded with 0
    for (std::size_t i = branch > kTestLength ? branch - kTestLength : 0; i < branch; ++i) {
        const int r = ldi_zero_register(code[i].w0);
        if (r >= 0) zeroed |= 1U << r;
    }
    for (unsigned r = 16; r < 31; ++r) {
        if ((zeroed >> r & 3U) == 3U) return true;
    }
    return false;
}

/// True if a test of a weak symbol's address branches past code[call].
bool guarded(const std::vector<Instruction>& code, std::size_t call) {
    const std::size_t first = call > kGuardWindow ? call - kGuardWindow : 0;
    for (std::size_t j = call; j-- > first;) {
        const avr::Flow& f = code[j].flow;
        if (f.kind == avr::Flow::Kind::kBranch && f.target && *f.target > code[call].pc &&
            tests_zero_address(code, j)) {
            return true;
        }
    }
    return false;
}

const char* mnemonic(const Instruction& in) {
    const bool call = in.flow.kind == avr::Flow::Kind::kCall;
    if ((in.w0 & 0xE000) == 0xC000) return call ? "rcall" : "rjmp";
    return call ? "call" : "jmp";
}

bool is_toolchain_name(const std::string& name) { return name.rfind("__", 0) == 0; }

std::vector<std::string> unresolved_weak(const ElfImage& elf) {
    std::vector<std::string> names;
    for (const ElfSymbol& s : elf.symbols()) {
        if (s.binding != ElfBinding::kWeak) continue;
        if (!s.defined || (s.address == 0 && !is_toolchain_name(s.name))) names.push_back(demangle(s.name));
    }
    std::sort(names.begin(), names.end());
    names.erase(std::unique(names.begin(), names.end()), names.end());
    return names;
}

}  // namespace

ZeroCallReport find_zero_calls(const ElfImage& elf) {
    std::map<uint32_t, ZeroCall> found;  // by address: overlapping symbols find a call once
    uint64_t decoded_to = 0;  // symbols come by address: one inside a decoded one is skipped
    for (const ElfSymbol& s : elf.symbols()) {
        if (!s.in_text || !s.defined || s.size == 0 || s.is_object) continue;
        // Within .text only: a damaged symbol table may claim any size.
        const uint64_t end = std::min<uint64_t>(uint64_t{s.address} + s.size, elf.text_end());
        if (end <= decoded_to || s.address >= end) continue;
        decoded_to = end;
        const std::vector<Instruction> code = decode_range(elf, s.address, static_cast<uint32_t>(end));
        for (std::size_t i = 0; i < code.size(); ++i) {
            const avr::Flow& f = code[i].flow;
            const bool transfer = f.kind == avr::Flow::Kind::kCall || f.kind == avr::Flow::Kind::kJump;
            if (!transfer || f.target != 0U) continue;
            if (found.count(code[i].pc) != 0 || guarded(code, i)) continue;
            const auto function = elf.function_at(code[i].pc);
            found[code[i].pc] = ZeroCall{code[i].pc, mnemonic(code[i]), demangle(function ? function->name : s.name)};
        }
    }
    ZeroCallReport report;
    for (auto& [pc, call] : found) report.calls.push_back(std::move(call));
    report.unresolved_weak = unresolved_weak(elf);
    return report;
}

std::vector<std::string> describe_zero_calls(const ZeroCallReport& report) {
    std::string candidates;
    const auto& weak = report.unresolved_weak;
    if (weak.size() == 1) {
        candidates = fmt::format(" (the ELF's unresolved weak symbol {} is the likely callee: nothing defines it)",
                                 weak.front());
    } else if (!weak.empty()) {
        candidates = fmt::format(" (the likely callee is one of the ELF's unresolved weak symbols, which nothing "
                                 "defines: {})",
                                 fmt::join(weak, ", "));
    }
    std::vector<std::string> lines;
    for (const ZeroCall& c : report.calls) {
        const std::string where = c.function.empty() ? std::string() : " in " + c.function;
        lines.push_back(fmt::format("`{} 0` at 0x{:04x}{}: an unguarded {} to address 0 restarts the firmware{}",
                                    c.instruction, c.pc, where, c.instruction.find("call") != std::string::npos
                                                                    ? "call" : "jump",
                                    candidates));
    }
    return lines;
}

}  // namespace ddmr::hil
