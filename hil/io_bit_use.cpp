#include "hil/io_bit_use.hpp"

#include <algorithm>
#include <utility>

#include "hil/avr_decode.hpp"

namespace ddmr::hil {
namespace {

// SREG bit numbers (AVR Instruction Set Manual, "The Status Register").
constexpr unsigned kZ = 1, kN = 2, kV = 3, kS = 4;

/// Rr of a two-register ALU instruction (AND, MOV: 0010 xxrd dddd rrrr).
unsigned rr5(uint16_t w0) { return (w0 & 0x0FU) | ((w0 >> 5) & 0x10U); }

/// True if `w0` loads Rd (bits 4..8) from data memory or I/O: IN, LD, LDD, LDS.
bool loads_register(uint16_t w0) {
    if ((w0 & 0xF800) == 0xB000) return true;  // IN
    const auto d = avr::decode_data_access(w0, 0);
    return d && !d->store;
}

}  // namespace

IoBitUse::IoBitUse(std::vector<uint16_t> registers, uint16_t io_begin, uint16_t io_end, uint16_t spl)
    : registers_(std::move(registers)), io_begin_(io_begin), io_end_(io_end), spl_(spl) {}

bool IoBitUse::tracked(uint16_t address) const {
    return std::find(registers_.begin(), registers_.end(), address) != registers_.end();
}

void IoBitUse::use(uint16_t address, uint8_t bits) {
    const auto it = std::find_if(used_.begin(), used_.end(), [address](const IoBits& p) { return p.address == address; });
    if (it == used_.end()) {
        used_.push_back({address, bits});
    } else {
        it->used = static_cast<uint8_t>(it->used | bits);
    }
}

void IoBitUse::use(const Taint& t) {
    if (t.bits != 0) use(t.source, t.bits);
}

// What an instruction the analysis does not follow reads of the taint is used.
void IoBitUse::use_operands(const StepAccess& a) {
    for (unsigned r = 0; r < 32; ++r) {
        if ((a.reg_reads >> r) & 1U) use(reg_[r]);
    }
    for (unsigned f = 0; f < 8; ++f) {
        if ((a.flag_reads >> f) & 1U) use(flag_[f]);
    }
}

void IoBitUse::clear_results(const StepAccess& a) {
    for (unsigned r = 0; r < 32; ++r) {
        if ((a.reg_writes >> r) & 1U) reg_[r] = {};
    }
    for (unsigned f = 0; f < 8; ++f) {
        if ((a.flag_writes >> f) & 1U) flag_[f] = {};
    }
}

// AND Rd, other, with Rd tainted and `other` not (or ANDI: a constant).
// A mask that may differ in another pass says nothing of that pass.
void IoBitUse::and_with(unsigned d, const Taint& other, uint8_t other_value, bool other_varies) {
    Taint result;
    if (other.bits != 0 || other_varies) {
        use(reg_[d]);
        use(other);
    } else {
        result = {reg_[d].source, static_cast<uint8_t>(reg_[d].bits & other_value)};
    }
    reg_[d] = result;
    flag_[kZ] = flag_[kN] = flag_[kS] = result;
    flag_[kV] = {};  // cleared
}

// The instructions that keep taint in place; false for any other.
bool IoBitUse::special(uint16_t w0, const StepAccess& a, const CpuView& cpu) {
    const unsigned d = (w0 >> 4) & 0x1FU;
    if (a.mem_read && a.count == 1 && tracked(a.address[0]) && loads_register(w0)) {
        use_operands(a);  // a pointer register
        clear_results(a);
        reg_[d] = {a.address[0], 0xFF};
        use(a.address[0], 0);
        return true;
    }
    if ((w0 & 0xFD00) == 0x9900) {  // SBIC, SBIS A, b: that bit only
        const auto address = static_cast<uint16_t>(((w0 >> 3) & 0x1FU) + 0x20U);
        if (!tracked(address)) return false;
        use(address, static_cast<uint8_t>(1U << (w0 & 7U)));
        return true;
    }
    if ((w0 & 0xFC08) == 0xFC00) {  // SBRC, SBRS Rr, b: that bit only
        use(Taint{reg_[d].source, static_cast<uint8_t>(reg_[d].bits & (1U << (w0 & 7U)))});
        return true;
    }
    if ((w0 & 0xFC00) == 0x2C00) {  // MOV
        reg_[d] = reg_[rr5(w0)];
        return true;
    }
    if ((w0 & 0xFF00) == 0x0100) {  // MOVW
        const unsigned dd = ((w0 >> 4) & 0x0FU) * 2, r = (w0 & 0x0FU) * 2;
        reg_[dd] = reg_[r];
        reg_[dd + 1] = reg_[r + 1];
        return true;
    }
    if ((w0 & 0xF000) == 0x7000) {  // ANDI Rd (16..31), K
        const unsigned rd = 16 + ((w0 >> 4) & 0x0FU);
        if (reg_[rd].bits == 0) return false;
        and_with(rd, {}, static_cast<uint8_t>(((w0 >> 4) & 0xF0U) | (w0 & 0x0FU)), false);
        return true;
    }
    if ((w0 & 0xFC00) == 0x2000) {  // AND Rd, Rr
        const unsigned r = rr5(w0);
        if (r == d) {  // TST: the flags only
            flag_[kZ] = flag_[kN] = flag_[kS] = reg_[d];
            flag_[kV] = {};
            return true;
        }
        if (reg_[d].bits == 0 && reg_[r].bits == 0) return false;
        if (reg_[d].bits == 0) {  // the taint is Rr's: Rd's value is the mask
            const Taint t = reg_[r];
            const bool mask_varies = ((reg_varies_ >> d) & 1U) != 0;
            reg_[d] = t;
            and_with(d, {}, cpu.data[d], mask_varies);
            return true;
        }
        and_with(d, reg_[r], cpu.data[r], ((reg_varies_ >> r) & 1U) != 0);
        return true;
    }
    return false;
}

void IoBitUse::note_varying(const StepAccess& a) {
    bool varies = (a.reg_reads & reg_varies_) != 0 || (a.flag_reads & flag_varies_) != 0;
    for (unsigned i = 0; i < a.count && a.mem_read; ++i) {
        const uint16_t address = a.address[i];
        const bool io = address >= io_begin_ && address < io_end_;
        if (io ? address != spl_ && address != spl_ + 1 : sram_varies_.count(address) != 0) varies = true;
    }
    reg_varies_ = varies ? reg_varies_ | a.reg_writes : reg_varies_ & ~a.reg_writes;
    flag_varies_ = static_cast<uint8_t>(varies ? flag_varies_ | a.flag_writes : flag_varies_ & ~a.flag_writes);
    for (unsigned i = 0; i < a.count && a.mem_write; ++i) {
        if (varies) {
            sram_varies_.insert(a.address[i]);
        } else {
            sram_varies_.erase(a.address[i]);
        }
    }
}

void IoBitUse::step(uint16_t w0, const StepAccess& a, const CpuView& cpu) {
    if (!special(w0, a, cpu)) {
        use_operands(a);
        clear_results(a);
        for (unsigned i = 0; i < a.count && a.mem_read; ++i) {
            if (tracked(a.address[i])) use(a.address[i], 0xFF);  // SBI/CBI on PINx, a POP...
        }
    }
    note_varying(a);
}

std::vector<IoBits> IoBitUse::finish() {
    for (Taint& t : reg_) use(std::exchange(t, {}));
    for (Taint& t : flag_) use(std::exchange(t, {}));
    return std::move(used_);
}

}  // namespace ddmr::hil
