#pragma once
// AVR instruction decoding for the HIL's code analyses (the race detector's
// walks around an interrupted instruction, its loop check): which data
// memory an instruction loads or stores, where it may transfer control,
// which registers it reads and writes. Not an emulator: simavr executes;
// this only classifies. Encodings: Atmel AVR Instruction Set Manual
// (DS40002198A), one per instruction there; a word that is none of the
// classified forms is reported as unknown, never guessed.
//
// Addresses are flash byte addresses (simavr's avr->pc); "k" of a branch is
// in words, as the manual gives it.

#include <cstdint>
#include <optional>

namespace ddmr::hil::avr {

/// The pointer a data access goes through (or none: LDS/STS k).
enum class Pointer { kNone, kX, kY, kZ };

/// A data-space load or store: LDS/STS, LD/ST X/Y/Z with post-increment or
/// pre-decrement, LDD/STD Y+q / Z+q.
struct DataAccess {
    bool store = false;       ///< ST/STS/STD (else a load)
    uint32_t words = 1;       ///< 2 for LDS/STS
    uint8_t reg = 0;          ///< Rd of a load, Rr of a store
    Pointer pointer = Pointer::kNone;
    uint16_t k = 0;           ///< LDS/STS data address
    uint16_t q = 0;           ///< LDD/STD displacement
    int pre = 0;              ///< -1: pre-decrement
    int post = 0;             ///< +1: post-increment
};

/// The load or store encoded by `w0` (and `w1`, the next word, for LDS/STS).
std::optional<DataAccess> decode_data_access(uint16_t w0, uint16_t w1);

/// Words of the instruction starting with `w0` (2 for LDS, STS, JMP, CALL).
uint32_t instruction_words(uint16_t w0);

/// Control flow of one instruction.
struct Flow {
    enum class Kind {
        kNext,         ///< falls through
        kSkip,         ///< CPSE/SBRC/SBRS/SBIC/SBIS: next, or skips the next instruction
        kBranch,       ///< BRBS/BRBC: next, or target
        kJump,         ///< RJMP/JMP: target only
        kCall,         ///< RCALL/CALL/ICALL/EICALL: a subroutine (target if direct)
        kIndirectJump, ///< IJMP/EIJMP: unknown target
        kReturn,       ///< RET/RETI
    };
    Kind kind = Kind::kNext;
    std::optional<uint32_t> target;  ///< flash byte address of a direct branch, jump or call
};

/// Control flow of the instruction at byte address `pc` (words w0, w1).
Flow decode_flow(uint16_t w0, uint16_t w1, uint32_t pc);

/// True if the instruction reads data memory or I/O: a load (LDS, LD, LDD),
/// IN, SBIC/SBIS, POP. (LPM reads flash, which firmware cannot change.)
bool reads_data_memory(uint16_t w0);

/// General-purpose registers an instruction reads and writes (bit n = Rn).
/// `known` is false for an instruction this decoder does not classify.
struct RegisterUse {
    uint32_t reads = 0;
    uint32_t writes = 0;
    bool known = false;
};
RegisterUse register_use(uint16_t w0);

}  // namespace ddmr::hil::avr
