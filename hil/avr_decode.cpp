#include "hil/avr_decode.hpp"

namespace ddmr::hil::avr {
namespace {

uint32_t bit(unsigned r) { return 1U << r; }
uint32_t pair(unsigned r) { return bit(r) | bit(r + 1); }

/// Rd of the 5-bit "d dddd" field (bits 8..4).
unsigned rd5(uint16_t w0) { return (w0 >> 4) & 0x1FU; }
/// Rr of the 5-bit "r rrrr" field (bit 9, bits 3..0).
unsigned rr5(uint16_t w0) { return (w0 & 0x0FU) | ((w0 >> 5) & 0x10U); }

uint32_t pointer_regs(Pointer p) {
    switch (p) {
        case Pointer::kX: return pair(26);
        case Pointer::kY: return pair(28);
        case Pointer::kZ: return pair(30);
        case Pointer::kNone: break;
    }
    return 0;
}

/// Sign-extends the low `bits` bits of `v`.
int32_t sign_extend(uint32_t v, unsigned bits) {
    const uint32_t m = 1U << (bits - 1);
    return static_cast<int32_t>((v ^ m) - m);
}

}  // namespace

std::optional<DataAccess> decode_data_access(uint16_t w0, uint16_t w1) {
    DataAccess a;
    a.reg = static_cast<uint8_t>(rd5(w0));
    // LD/ST family: 1001 00sd dddd nnnn (s = 1: store).
    if ((w0 & 0xFC00) == 0x9000) {
        a.store = (w0 & 0x0200) != 0;
        switch (w0 & 0x000F) {
            case 0x0: a.words = 2; a.k = w1; return a;                       // LDS / STS k
            case 0xC: a.pointer = Pointer::kX; return a;                     // X
            case 0xD: a.pointer = Pointer::kX; a.post = 1; return a;         // X+
            case 0xE: a.pointer = Pointer::kX; a.pre = -1; return a;         // -X
            case 0x9: a.pointer = Pointer::kY; a.post = 1; return a;         // Y+
            case 0xA: a.pointer = Pointer::kY; a.pre = -1; return a;         // -Y
            case 0x1: a.pointer = Pointer::kZ; a.post = 1; return a;         // Z+
            case 0x2: a.pointer = Pointer::kZ; a.pre = -1; return a;         // -Z
            default: return std::nullopt;  // LPM, ELPM, POP, PUSH, XCH, ...: not a data access here
        }
    }
    // LDD/STD Rd,Y+q / Z+q: 10q0 qqsd dddd yqqq (LD/ST Y or Z is q = 0).
    if ((w0 & 0xD000) == 0x8000) {
        a.store = (w0 & 0x0200) != 0;
        a.pointer = (w0 & 0x0008) != 0 ? Pointer::kY : Pointer::kZ;
        a.q = static_cast<uint16_t>(((w0 >> 8) & 0x20) | ((w0 >> 7) & 0x18) | (w0 & 0x07));
        return a;
    }
    return std::nullopt;
}

uint32_t instruction_words(uint16_t w0) {
    if ((w0 & 0xFC0F) == 0x9000) return 2;  // LDS, STS
    if ((w0 & 0xFE0C) == 0x940C) return 2;  // JMP 1001 010k kkkk 110k, CALL ... 111k
    return 1;
}

Flow decode_flow(uint16_t w0, uint16_t w1, uint32_t pc) {
    Flow f;
    const auto relative = [&](int32_t k_words) {
        return static_cast<uint32_t>(static_cast<int64_t>(pc) + 2 + 2 * static_cast<int64_t>(k_words));
    };
    if ((w0 & 0xE000) == 0xC000) {  // RJMP 1100 / RCALL 1101 kkkk kkkk kkkk
        f.kind = (w0 & 0x1000) != 0 ? Flow::Kind::kCall : Flow::Kind::kJump;
        f.target = relative(sign_extend(w0 & 0x0FFFU, 12));
        return f;
    }
    if ((w0 & 0xFE0C) == 0x940C) {  // JMP / CALL k (22-bit word address)
        f.kind = (w0 & 0x0002) != 0 ? Flow::Kind::kCall : Flow::Kind::kJump;
        const uint32_t k = ((static_cast<uint32_t>(w0 & 0x01F0) >> 3 | (w0 & 0x0001U)) << 16) | w1;
        f.target = 2 * k;
        return f;
    }
    if ((w0 & 0xF800) == 0xF000) {  // BRBS 1111 00kk kkkk ksss / BRBC 1111 01..
        f.kind = Flow::Kind::kBranch;
        f.target = relative(sign_extend((w0 >> 3) & 0x7FU, 7));
        return f;
    }
    if ((w0 & 0xFC00) == 0x1000 ||   // CPSE
        (w0 & 0xFC08) == 0xFC00 ||   // SBRC 1111 110r rrrr 0bbb, SBRS 1111 111r rrrr 0bbb
        (w0 & 0xFD00) == 0x9900) {   // SBIC 1001 1001, SBIS 1001 1011
        f.kind = Flow::Kind::kSkip;
        return f;
    }
    switch (w0) {
        case 0x9409: case 0x9419: f.kind = Flow::Kind::kIndirectJump; return f;  // IJMP, EIJMP
        case 0x9509: case 0x9519: f.kind = Flow::Kind::kCall; return f;          // ICALL, EICALL
        case 0x9508: case 0x9518: f.kind = Flow::Kind::kReturn; return f;        // RET, RETI
        default: break;
    }
    return f;
}

bool reads_data_memory(uint16_t w0) {
    if (const auto a = decode_data_access(w0, 0)) return !a->store;
    return (w0 & 0xF800) == 0xB000 ||  // IN 1011 0AAd dddd AAAA
           (w0 & 0xFD00) == 0x9900 ||  // SBIC, SBIS
           (w0 & 0xFE0F) == 0x900F;    // POP
}

RegisterUse register_use(uint16_t w0) {
    RegisterUse u;
    u.known = true;
    const unsigned d = rd5(w0);
    const unsigned r = rr5(w0);
    if (w0 == 0x0000) return u;  // NOP
    if ((w0 & 0xFF00) == 0x0100) {  // MOVW Rd+1:Rd, Rr+1:Rr
        u.reads = pair(2 * (w0 & 0x0FU));
        u.writes = pair(2 * ((w0 >> 4) & 0x0FU));
        return u;
    }
    if ((w0 & 0xFF00) == 0x0200) {  // MULS R16..31
        u.reads = bit(16 + ((w0 >> 4) & 0x0FU)) | bit(16 + (w0 & 0x0FU));
        u.writes = pair(0);
        return u;
    }
    if ((w0 & 0xFF00) == 0x0300) {  // MULSU, FMUL, FMULS, FMULSU: R16..23
        u.reads = bit(16 + ((w0 >> 4) & 0x07U)) | bit(16 + (w0 & 0x07U));
        u.writes = pair(0);
        return u;
    }
    if (w0 >= 0x0400 && w0 < 0x3000) {  // two-operand ALU 0000 01.. .. 0010 11..
        const unsigned op = w0 >> 10;
        const bool compare = op == 0x01 || op == 0x04 || op == 0x05;  // CPC, CPSE, CP
        const bool clear = d == r && (op == 0x09 || op == 0x06);     // EOR/SUB Rd,Rd: the value is 0
        if (op == 0x0B) {  // MOV
            u.reads = bit(r);
        } else if (!clear) {
            u.reads = bit(d) | bit(r);
        }
        if (!compare) u.writes = bit(d);
        return u;
    }
    if ((w0 & 0xF000) == 0x3000) {  // CPI R16..31
        u.reads = bit(16 + ((w0 >> 4) & 0x0FU));
        return u;
    }
    if (w0 >= 0x4000 && w0 < 0x8000) {  // SBCI, SUBI, ORI, ANDI R16..31
        u.reads = u.writes = bit(16 + ((w0 >> 4) & 0x0FU));
        return u;
    }
    if ((w0 & 0xF000) == 0xE000) {  // LDI
        u.writes = bit(16 + ((w0 >> 4) & 0x0FU));
        return u;
    }
    if (const auto a = decode_data_access(w0, 0)) {
        const uint32_t ptr = pointer_regs(a->pointer);
        u.reads = ptr | (a->store ? bit(a->reg) : 0U);
        u.writes = (a->pre != 0 || a->post != 0 ? ptr : 0U) | (a->store ? 0U : bit(a->reg));
        return u;
    }
    if ((w0 & 0xFE0E) == 0x9004) {  // LPM Rd,Z / Z+
        u.reads = pair(30);
        u.writes = bit(d) | ((w0 & 1U) != 0 ? pair(30) : 0U);
        return u;
    }
    if ((w0 & 0xFE0F) == 0x900F) { u.writes = bit(d); return u; }  // POP
    if ((w0 & 0xFE0F) == 0x920F) { u.reads = bit(d); return u; }   // PUSH
    if ((w0 & 0xFE00) == 0x9400) {
        switch (w0 & 0x000F) {
            case 0x0: case 0x1: case 0x2: case 0x3: case 0x5: case 0x6: case 0x7: case 0xA:
                u.reads = u.writes = bit(d);  // COM NEG SWAP INC ASR LSR ROR DEC
                return u;
            default: break;
        }
    }
    if ((w0 & 0xFF0F) == 0x9408) return u;  // BSET / BCLR (SEI, CLI, SEC, ...)
    switch (w0) {
        case 0x9588: case 0x9598: case 0x95A8: return u;           // SLEEP, BREAK, WDR
        case 0x95C8: u.reads = pair(30); u.writes = bit(0); return u;  // LPM (R0)
        case 0x9409: case 0x9419: u.reads = pair(30); return u;    // IJMP, EIJMP
        case 0x9508: case 0x9518: return u;                        // RET, RETI
        default: break;
    }
    if ((w0 & 0xFE00) == 0x9600) {  // ADIW, SBIW: R24, 26, 28, 30 pairs
        u.reads = u.writes = pair(24 + 2 * ((w0 >> 4) & 0x03U));
        return u;
    }
    if ((w0 & 0xFC00) == 0x9C00) {  // MUL
        u.reads = bit(d) | bit(r);
        u.writes = pair(0);
        return u;
    }
    if ((w0 & 0xFC00) == 0x9800) return u;  // CBI, SBIC, SBI, SBIS
    if ((w0 & 0xF800) == 0xB000) { u.writes = bit(d); return u; }  // IN
    if ((w0 & 0xF800) == 0xB800) { u.reads = bit(d); return u; }   // OUT (Rr in the d field)
    if ((w0 & 0xF000) == 0xC000) return u;                         // RJMP
    if ((w0 & 0xF800) == 0xF000) return u;                         // BRBS, BRBC
    if ((w0 & 0xFE08) == 0xF800) { u.reads = u.writes = bit(d); return u; }  // BLD
    if ((w0 & 0xFE08) == 0xFA00) { u.reads = bit(d); return u; }             // BST
    if ((w0 & 0xFC08) == 0xFC00) { u.reads = bit(d); return u; }             // SBRC, SBRS
    if ((w0 & 0xFE0C) == 0x940C && (w0 & 0x0002) == 0) return u;              // JMP
    u.known = false;  // CALL, RCALL, ICALL and anything not classified above
    return u;
}

}  // namespace ddmr::hil::avr
