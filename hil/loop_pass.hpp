#pragma once
// LoopPass: what one pass of a polling loop touches, and whether whole
// passes of it can be skipped exactly (hil/fast_forward.hpp).
//
// A pass is the instructions executed from an anchor PC back to the same PC
// with the same stack pointer. For each instruction, step_access() lists,
// before it runs, the data-space bytes it reads and writes (registers are
// data addresses 0..31, as in simavr; each flag of SREG is a location of
// its own, as the manual's "Flags" column of each instruction gives it; SP
// is read and written by PUSH, POP, CALL, RET). Encodings: Atmel
// AVR Instruction Set Manual (DS40002198A); an instruction not classified
// here refuses the loop, never a guess.
//
// analyse_pass() then finds the pass's loop-carried bytes: those it reads
// before writing them and also writes. If every carried byte holds the same
// value at the end of a pass as at its start, and nothing else changes the
// bytes the pass reads (no interrupt, no peripheral event: the jump stops
// before each one), every later pass on the same path computes the same
// thing from the same inputs, apart from what it recomputes from the timer
// counts it reads. Pure: no simavr here.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace ddmr::hil {

/// The CPU state step_access() needs: data space (registers at 0..31), SP.
struct CpuView {
    const uint8_t* data = nullptr;
    uint16_t sp = 0;
    uint16_t sreg_address = 0x5F;
    uint16_t pc_bytes = 2;  ///< bytes of a return address on the stack
};

/// The data-space bytes one instruction touches.
struct StepAccess {
    uint32_t reg_reads = 0;   ///< bit n: reads Rn
    uint32_t reg_writes = 0;  ///< bit n: writes Rn
    uint8_t flag_reads = 0;   ///< SREG bits it reads (bit 0 C ... bit 7 I)
    uint8_t flag_writes = 0;  ///< SREG bits it writes
    bool sp_rw = false;       ///< PUSH, POP, CALL, RET: SP read and written
    uint8_t count = 0;        ///< bytes of memory (not registers) in address
    std::array<uint16_t, 3> address{};
    bool mem_read = false;    ///< the bytes are read
    bool mem_write = false;   ///< the bytes are written
    /// Why no loop containing this instruction is skipped (nullptr: none).
    const char* refusal = nullptr;
};

/// What the instruction at the PC (words w0, w1) touches, given the CPU
/// state just before it runs.
StepAccess step_access(uint16_t w0, uint16_t w1, const CpuView& cpu);

/// One recorded pass: per instruction, its PC and what it touched.
struct RecordedStep {
    uint32_t pc = 0;
    uint16_t sp = 0;  ///< SP before it ran
    StepAccess access;
    uint32_t cycles_after = 0;  ///< cycles from the pass's start to the end of this instruction
};

/// The verdict on a pass.
struct PassAnalysis {
    std::string refusal;                 ///< empty: the loop may be skipped
    std::vector<uint16_t> carried;       ///< data addresses read first, then written (registers included)
    uint8_t carried_flags = 0;           ///< SREG bits read before written, and written
    std::vector<uint16_t> io_reads;      ///< I/O addresses read (sorted, unique)
    std::vector<uint16_t> io_writes;     ///< I/O addresses written (sorted, unique)
};

/// Analyses one pass. I/O is [io_begin, io_end) in data space (0x20 up to
/// the first SRAM byte); SREG's flags are their own locations, SP's two
/// bytes (SPL at spl_address) are read and written by PUSH, POP, CALL, RET.
PassAnalysis analyse_pass(const std::vector<RecordedStep>& steps, uint16_t io_begin, uint16_t io_end,
                          uint16_t spl_address);

}  // namespace ddmr::hil
