#pragma once
// TornReadDetector: finds, on a real run, every multi-byte read of a watched
// SRAM variable that an ISR splits between its bytes (issue 6, shared-variable
// races), with nothing added to the firmware and no single-stepping.
//
// Signals:
//   in  avr_get_interrupt_irq(avr, v)[AVR_INT_IRQ_RUNNING] of each writer
//       vector (all vectors if any variable accepts "any ISR"): 1 = entry,
//       0 = RETI
//   reads SP, the return address on the stack, X/Y/Z, flash, the variable's
//       bytes (avr->data, no side effects)
//
// How (checked against simavr 1.6, sim_interrupts.c / sim_core.c): simavr
// takes an interrupt only between instructions; at entry it has pushed the
// return address as a word address, high byte at SP+1 and low byte at SP+2,
// and reports RUNNING = 1 with PC at the vector. The return address is the
// first instruction of the interrupted code that has not run. At each entry
// of a writer ISR the detector decodes the code around it:
//   - backwards from the return address: the loads that just ran, and
//   - forwards: the loads that will run after RETI,
// each walk going over consecutive load instructions only and stopping at
// the first other instruction, at a second load of a byte it has already
// seen (an earlier or later read of the same variable), or at a load whose
// pointer is no longer known. A read is split when some of the variable's
// bytes were loaded before the entry (set B) and some are still to load (A).
// Then the variable's bytes are copied at entry and again at the ISR's RETI:
//   value_before = bytes at entry, value_after = bytes at RETI (the true value),
//   value_read   = bytes in B from value_before, all others from value_after
//                  (what the interrupted code ends up with, assuming no other
//                  ISR writes the variable before its remaining loads).
// A split read is recorded as a TornRead when the ISR changed the variable;
// it is `visible` when value_read equals neither value_before nor
// value_after (e.g. a 32-bit counter read low byte first: an increment only
// tears visibly when its carry crosses into a byte that is still to load).
//
// Recognised load instructions (AVR instruction set manual):
//   LDS Rd,k          1001 000d dddd 0000  kkkk kkkk kkkk kkkk   (32-bit)
//   LD  Rd,X / X+ / -X   1001 000d dddd 1100 / 1101 / 1110
//   LD  Rd,Y+ / -Y       1001 000d dddd 1001 / 1010
//   LD  Rd,Z+ / -Z       1001 000d dddd 0001 / 0010
//   LDD Rd,Y+q / Z+q     10q0 qq0d dddd 1qqq / 0qqq   (LD Rd,Y / Z is q = 0)
// Loads of other addresses inside the walk are stepped over (their pointer
// updates are followed). Pointer addresses come from the registers at entry:
// a backward walk undoes post-increments / pre-decrements; a load into a
// pointer register (r26..r31) makes that pointer unknown beyond it.
// Decoding backwards is unambiguous on the ATmega328P: the second word of a
// two-word instruction (LDS/STS address <= RAMEND 0x8FF, CALL/JMP word
// address < 0x4000) is always below 0x8000, and every recognised load's
// first word is >= 0x8000.
//
// It misses (by design): reads whose bytes are spread over other
// instructions (arithmetic or branches between the loads, e.g. a byte-wise
// loop, or a load via a pointer register computed between loads), reads
// done with LPM/ELPM or by the hardware, a read split by an ISR that is not
// listed as a writer, a second ISR hitting the same read (recorded as a
// second event, each with its own before/after), and writes that tear (main
// code storing a variable the ISR reads). Walks stop after kMaxWalk
// instructions each way.
//
// Callbacks never allocate beyond the records reserved at construction (a
// record past the capacity is counted, not kept) and never throw. Construct
// after the AvrCore and destroy before; hooks are removed on destruction.

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "hil/atmega328p.hpp"
#include "hil/avr_core.hpp"
#include "hil/cycle_time.hpp"
#include "hil/elf_image.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// A variable to watch and the ISRs that write it.
struct WatchedVariable {
    std::string name;          ///< ELF data object (as avr-nm lists it), 2..8 bytes
    std::vector<int> writers;  ///< vector numbers (table 12-6) whose ISRs write it; empty = any ISR
};

struct TornReadConfig {
    /// Default: the reference sketch's encoder counters, written by encoder1()
    /// (INT0) and encoder2() (INT1).
    std::vector<WatchedVariable> variables = {{"Count1", {atmega328p::vector::kInt0}},
                                              {"Count2", {atmega328p::vector::kInt1}}};
    /// Records kept (reserved up front); later ones are only counted.
    std::size_t record_capacity = 4096;
};

/// A read split by an ISR that changed the variable.
struct TornRead {
    Cycles cycle = 0;          ///< entry of the splitting ISR
    std::size_t variable = 0;  ///< index into TornReadDetector::variables()
    int vector = 0;            ///< the ISR
    uint32_t resume_pc = 0;    ///< flash byte address the interrupted code resumes at
    uint8_t loaded_before = 0; ///< bit i: byte i was loaded before the ISR
    uint64_t value_before = 0; ///< variable at ISR entry (little-endian bytes)
    uint64_t value_read = 0;   ///< what the interrupted read yields
    uint64_t value_after = 0;  ///< variable after the ISR (the true value)
    bool visible = false;      ///< value_read is neither value_before nor value_after
};

struct TornReadStats {
    uint64_t entries_checked = 0;  ///< writer-ISR entries looked at
    uint64_t split_reads = 0;      ///< (entry, variable) pairs with a read in progress
    uint64_t torn = 0;             ///< split reads the ISR changed the variable in
    uint64_t visible = 0;          ///< torn reads with a value that never existed
    uint64_t dropped = 0;          ///< torn reads past record_capacity
};

/// The loads of one variable around a resume address (exposed for tests).
struct ReadSplit {
    uint8_t before = 0;  ///< bit i: byte i loaded by the instructions just before
    uint8_t after = 0;   ///< bit i: byte i loaded by the instructions from the resume address
    bool split() const { return before != 0 && after != 0; }
};

/// Pointer registers X, Y, Z at the interrupt (data-space values).
struct PointerRegs {
    uint16_t x = 0, y = 0, z = 0;
};

/// Decodes the loads around `resume_pc` (flash byte address) as described
/// above, for the variable at data address [address, address + size).
ReadSplit find_read_split(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs,
                          uint16_t address, uint16_t size);

class TornReadDetector {
public:
    static constexpr int kMaxWalk = 16;  ///< instructions decoded each way
    static constexpr int kMaxNesting = 8;

    /// Resolves every variable in `elf` (throws std::invalid_argument naming a
    /// missing symbol, a size outside 2..8, or a vector outside 1..25).
    TornReadDetector(AvrCore& core, const ElfImage& elf, const TornReadConfig& config = {});
    ~TornReadDetector();
    TornReadDetector(const TornReadDetector&) = delete;
    TornReadDetector& operator=(const TornReadDetector&) = delete;

    const std::vector<TornRead>& records() const { return records_; }
    const TornReadStats& stats() const { return stats_; }
    /// Counts for one variable (index into variables()).
    const TornReadStats& stats(std::size_t variable) const { return per_variable_[variable]; }
    const std::vector<WatchedVariable>& variables() const { return config_.variables; }
    const std::string& name(const TornRead& r) const { return config_.variables[r.variable].name; }

private:
    struct Var {
        uint16_t address = 0;
        uint16_t size = 0;
        uint32_t writer_mask = 0;  ///< bit v: vector v writes it (all bits: any)
    };
    struct Hook {
        TornReadDetector* self = nullptr;
        int vector = 0;
        avr_irq_t* irq = nullptr;
    };
    /// An ISR entry in progress with the reads it split.
    struct Frame {
        int vector = 0;
        Cycles entry = 0;
        uint32_t resume_pc = 0;
        std::size_t first = 0;  ///< index into pending_ (nvars per frame)
    };
    struct Pending {
        bool active = false;
        uint8_t before_mask = 0;
        std::array<uint8_t, 8> bytes{};
    };

    static void on_running(avr_irq_t* irq, uint32_t value, void* param);
    void enter(int vector);
    void leave(int vector);

    AvrCore& core_;
    TornReadConfig config_;
    std::vector<Var> vars_;
    std::vector<Hook> hooks_;
    std::array<Frame, kMaxNesting> frames_{};
    int depth_ = 0;
    std::vector<Pending> pending_;  ///< kMaxNesting x vars_.size()
    std::vector<TornRead> records_;
    TornReadStats stats_;
    std::vector<TornReadStats> per_variable_;
};

}  // namespace ddmr::hil
