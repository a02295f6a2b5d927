#pragma once
// IoBitUse: which bits of the I/O registers followed (the PIN registers,
// the timers' interrupt flag registers TIFRn) one pass of a loop reads can
// change what the pass does. `digitalRead(7)` loads the whole of PIND and
// keeps bit 7 (`ld r30, X` then `and r30, r29`, the mask from the core's
// flash table): an encoder's edge on PD2 changes a register for two
// instructions and nothing after. `micros()` loads TIFR0 and tests TOV0
// only: a compare match that sets OCF0A changes nothing it does.
// Fast-forward may then raise that edge, or run that compare match, after a
// jump instead of ending the jump before it (hil/pin_edge_reach.hpp,
// hil/timer_event_reach.hpp).
//
// A taint analysis along one recorded pass, fed each instruction before it
// runs (with the CPU state then). A register loaded from a followed I/O
// register (IN, LD, LDD, LDS) carries the source's bits in place; only
// these keep them: MOV and MOVW copy them; AND with a value that is the
// same in every pass, and ANDI, clear the bits the mask clears (AND's flags
// take what is left); SBRS/SBRC and SBIS/SBIC on a tracked bit use that bit
// only. Any other instruction that reads a tainted register or flag, and
// whatever is still tainted when the pass ends, makes its bits "used"
// (AVR Instruction Set Manual, DS40002198A, each instruction's operation).
//
// "The same in every pass": every pass on one path starts from the same
// carried bytes (fast-forward checks them), so a value differs between
// passes only if it derives from an I/O read (a timer count, a pin). Such
// values are followed through registers, flags and SRAM, conservatively
// (an instruction's results vary if any operand does), and an AND with one
// of them as its mask makes its tainted bits used. Pure: no simavr here.

#include <cstdint>
#include <unordered_set>
#include <vector>

#include "hil/loop_pass.hpp"

namespace ddmr::hil {

/// The bits of one followed I/O register whose value can change what a pass does.
struct IoBits {
    uint16_t address = 0;  ///< the register's data address
    uint8_t used = 0;      ///< bit n: its bit n is used
};

class IoBitUse {
public:
    /// `registers`: the data addresses of the I/O registers to follow.
    /// [io_begin, io_end) is the I/O space; SPL at `spl` (SP is the same at
    /// each point of a path: its reads do not vary).
    IoBitUse(std::vector<uint16_t> registers, uint16_t io_begin, uint16_t io_end, uint16_t spl);

    /// The instruction (first word `w0`, its access from step_access())
    /// about to run on `cpu`.
    void step(uint16_t w0, const StepAccess& access, const CpuView& cpu);

    /// Ends the pass: the followed registers it read, each with its used bits.
    [[nodiscard]] std::vector<IoBits> finish();

private:
    struct Taint {
        uint16_t source = 0;  ///< the followed register's data address
        uint8_t bits = 0;     ///< its bits, in place; 0: untainted
    };
    [[nodiscard]] bool tracked(uint16_t address) const;
    void use(const Taint& t);
    void use(uint16_t address, uint8_t bits);
    void use_operands(const StepAccess& access);
    void clear_results(const StepAccess& access);
    bool special(uint16_t w0, const StepAccess& access, const CpuView& cpu);
    void and_with(unsigned d, const Taint& other, uint8_t other_value, bool other_varies);
    void note_varying(const StepAccess& access);

    std::vector<uint16_t> registers_;
    uint16_t io_begin_, io_end_, spl_;
    Taint reg_[32];
    Taint flag_[8];
    std::vector<IoBits> used_;  ///< per followed register read
    uint32_t reg_varies_ = 0;
    uint8_t flag_varies_ = 0;
    std::unordered_set<uint16_t> sram_varies_;
};

}  // namespace ddmr::hil
