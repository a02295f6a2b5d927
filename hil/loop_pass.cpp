#include "hil/loop_pass.hpp"

#include <algorithm>
#include <map>

#include "hil/avr_decode.hpp"

namespace ddmr::hil {
namespace {

uint16_t pointer_value(const CpuView& cpu, avr::Pointer p) {
    const unsigned low = p == avr::Pointer::kX ? 26U : p == avr::Pointer::kY ? 28U : 30U;
    return static_cast<uint16_t>(cpu.data[low] | (cpu.data[low + 1] << 8));
}

void add_byte(StepAccess& a, uint16_t address) {
    if (a.count < a.address.size()) a.address[a.count++] = address;
}

constexpr uint8_t kArith = 0x3F;  ///< H S V N Z C
constexpr uint8_t kLogic = 0x1E;  ///< S V N Z (V cleared)
constexpr uint8_t kShift = 0x1F;  ///< S V N Z C
constexpr uint8_t kC = 0x01, kZ = 0x02, kT = 0x40;

/// The flags an instruction reads and writes (AVR Instruction Set Manual,
/// each instruction's "Flags" column and operation).
void classify_flags(uint16_t w0, StepAccess& a) {
    const auto rw = [&a](uint8_t reads, uint8_t writes) {
        a.flag_reads = reads;
        a.flag_writes = writes;
    };
    if (w0 >= 0x0400 && w0 < 0x3000) {  // two-operand ALU, by its 6-bit opcode
        switch (w0 >> 10) {
            case 0x01: case 0x02: return rw(kC | kZ, kArith);  // CPC, SBC (Z: the chain's previous Z)
            case 0x03: case 0x05: case 0x06: return rw(0, kArith);  // ADD, CP, SUB
            case 0x07: return rw(kC, kArith);                       // ADC
            case 0x08: case 0x09: case 0x0A: return rw(0, kLogic);  // AND, EOR, OR
            default: return;                                        // CPSE, MOV
        }
    }
    if ((w0 & 0xF000) == 0x3000 || (w0 & 0xF000) == 0x5000) return rw(0, kArith);  // CPI, SUBI
    if ((w0 & 0xF000) == 0x4000) return rw(kC | kZ, kArith);                        // SBCI
    if ((w0 & 0xE000) == 0x6000) return rw(0, kLogic);                              // ORI, ANDI
    if ((w0 & 0xFF00) == 0x0200 || (w0 & 0xFF00) == 0x0300 || (w0 & 0xFC00) == 0x9C00) {
        return rw(0, kC | kZ);  // MULS, MULSU/FMUL*, MUL
    }
    if ((w0 & 0xFE00) == 0x9600) return rw(0, kShift);  // ADIW, SBIW
    if ((w0 & 0xFF0F) == 0x9408) return rw(0, static_cast<uint8_t>(1U << ((w0 >> 4) & 7U)));  // BSET, BCLR
    if ((w0 & 0xFE00) == 0x9400) {
        switch (w0 & 0x000F) {
            case 0x0: case 0x5: case 0x6: return rw(0, kShift);  // COM, ASR, LSR
            case 0x1: return rw(0, kArith);                      // NEG
            case 0x3: case 0xA: return rw(0, kLogic);            // INC, DEC
            case 0x7: return rw(kC, kShift);                     // ROR
            default: return;
        }
    }
    if ((w0 & 0xF800) == 0xF000) return rw(static_cast<uint8_t>(1U << (w0 & 7U)), 0);  // BRBS, BRBC
    if ((w0 & 0xFE08) == 0xF800) return rw(kT, 0);  // BLD
    if ((w0 & 0xFE08) == 0xFA00) return rw(0, kT);  // BST
}

/// IN/OUT's A field (0..63) as a data address.
uint16_t io6(uint16_t w0) { return static_cast<uint16_t>((((w0 >> 5) & 0x30U) | (w0 & 0x0FU)) + 0x20U); }

/// Stack and I/O instructions; false if `w0` is none of them.
bool stack_or_io(uint16_t w0, const CpuView& cpu, StepAccess& a) {
    const bool call = (w0 & 0xFE0E) == 0x940E || (w0 & 0xF000) == 0xD000 || w0 == 0x9509;
    if (call) {  // CALL, RCALL, ICALL: the return address is pushed at SP, SP-1[, SP-2]
        a.sp_rw = a.mem_write = true;
        for (uint16_t i = 0; i < cpu.pc_bytes; ++i) add_byte(a, static_cast<uint16_t>(cpu.sp - i));
        if (w0 == 0x9509) a.reg_reads = (1U << 30) | (1U << 31);
        return true;
    }
    if (w0 == 0x9508) {  // RET
        a.sp_rw = a.mem_read = true;
        for (uint16_t i = 1; i <= cpu.pc_bytes; ++i) add_byte(a, static_cast<uint16_t>(cpu.sp + i));
        return true;
    }
    const unsigned d = (w0 >> 4) & 0x1FU;
    if ((w0 & 0xFE0F) == 0x920F || (w0 & 0xFE0F) == 0x900F) {  // PUSH, POP
        const bool push = (w0 & 0x0200) != 0;
        a.sp_rw = true;
        (push ? a.mem_write : a.mem_read) = true;
        add_byte(a, push ? cpu.sp : static_cast<uint16_t>(cpu.sp + 1));
        (push ? a.reg_reads : a.reg_writes) = 1U << d;
        return true;
    }
    if ((w0 & 0xF000) == 0xB000) {  // IN (1011 0) / OUT (1011 1)
        const bool out = (w0 & 0x0800) != 0;
        const uint16_t addr = io6(w0);
        (out ? a.reg_reads : a.reg_writes) = 1U << d;
        if (addr == cpu.sreg_address) {
            (out ? a.flag_writes : a.flag_reads) = 0xFF;
        } else {
            (out ? a.mem_write : a.mem_read) = true;
            add_byte(a, addr);
        }
        return true;
    }
    if ((w0 & 0xFC00) == 0x9800) {  // CBI 1001 1000, SBIC 1001 1001, SBI 1001 1010, SBIS 1001 1011
        a.mem_read = true;
        a.mem_write = (w0 & 0x0100) == 0;
        add_byte(a, static_cast<uint16_t>(((w0 >> 3) & 0x1FU) + 0x20U));
        return true;
    }
    return false;
}

const char* refusal_of(uint16_t w0) {
    switch (w0) {
        case 0x9588: return "sleeps";
        case 0x9598: return "has a BREAK";
        case 0x95A8: return "resets the watchdog (WDR)";
        case 0x95E8: case 0x95F8: return "writes flash (SPM)";
        case 0x9518: return "returns from an interrupt (RETI)";
        case 0x9519: case 0x9419: return "jumps through EIND (EICALL/EIJMP)";
        default: return nullptr;
    }
}

/// SREG's flags as pseudo-addresses past the 64 KiB data space's use (0xFFF8 + bit).
constexpr uint16_t kFlagBase = 0xFFF8;

}  // namespace

StepAccess step_access(uint16_t w0, uint16_t w1, const CpuView& cpu) {
    StepAccess a;
    if ((a.refusal = refusal_of(w0)) != nullptr) return a;
    classify_flags(w0, a);
    if (stack_or_io(w0, cpu, a)) return a;
    if (const auto d = avr::decode_data_access(w0, w1)) {
        uint16_t addr = d->k;
        if (d->pointer != avr::Pointer::kNone) {
            addr = static_cast<uint16_t>(pointer_value(cpu, d->pointer) + d->q + d->pre);
        }
        if (addr == cpu.sreg_address) {
            (d->store ? a.flag_writes : a.flag_reads) = 0xFF;
        } else {
            (d->store ? a.mem_write : a.mem_read) = true;
            add_byte(a, addr);
        }
    }
    const avr::RegisterUse use = avr::register_use(w0);
    if (!use.known) {
        a.refusal = "has an instruction the decoder does not classify";
        return a;
    }
    a.reg_reads |= use.reads;
    a.reg_writes |= use.writes;
    return a;
}

PassAnalysis analyse_pass(const std::vector<RecordedStep>& steps, uint16_t io_begin, uint16_t io_end,
                          uint16_t spl_address) {
    PassAnalysis out;
    enum class First : uint8_t { kRead, kWrite };
    std::map<uint16_t, std::pair<First, bool>> seen;  // address -> first access, written
    const auto touch = [&](uint16_t addr, bool write) {
        auto [it, fresh] = seen.try_emplace(addr, write ? First::kWrite : First::kRead, write);
        if (!fresh && write) it->second.second = true;
    };
    const auto touch_regs = [&](uint32_t mask, bool write) {
        for (uint16_t r = 0; r < 32; ++r) {
            if ((mask >> r) & 1U) touch(r, write);
        }
    };
    for (const RecordedStep& s : steps) {
        const StepAccess& a = s.access;
        if (a.refusal != nullptr && out.refusal.empty()) out.refusal = a.refusal;
        // An instruction reads its operands before it writes its results.
        touch_regs(a.reg_reads, false);
        for (uint16_t f = 0; f < 8; ++f) {
            if ((a.flag_reads >> f) & 1U) touch(static_cast<uint16_t>(kFlagBase + f), false);
        }
        if (a.sp_rw) touch(spl_address, false), touch(static_cast<uint16_t>(spl_address + 1), false);
        for (uint8_t i = 0; i < a.count; ++i) {
            if (a.mem_read) touch(a.address[i], false);
        }
        touch_regs(a.reg_writes, true);
        for (uint16_t f = 0; f < 8; ++f) {
            if ((a.flag_writes >> f) & 1U) touch(static_cast<uint16_t>(kFlagBase + f), true);
        }
        if (a.sp_rw) touch(spl_address, true), touch(static_cast<uint16_t>(spl_address + 1), true);
        for (uint8_t i = 0; i < a.count; ++i) {
            const uint16_t addr = a.address[i];
            if (a.mem_write) touch(addr, true);
            if (addr < io_begin || addr >= io_end) continue;
            if (a.mem_read) out.io_reads.push_back(addr);
            if (a.mem_write) out.io_writes.push_back(addr);
        }
    }
    for (const auto& [addr, st] : seen) {
        if (st.first != First::kRead || !st.second) continue;
        if (addr >= kFlagBase) {
            out.carried_flags = static_cast<uint8_t>(out.carried_flags | (1U << (addr - kFlagBase)));
        } else {
            out.carried.push_back(addr);
        }
    }
    for (auto* v : {&out.io_reads, &out.io_writes}) {
        std::sort(v->begin(), v->end());
        v->erase(std::unique(v->begin(), v->end()), v->end());
    }
    return out;
}

}  // namespace ddmr::hil
