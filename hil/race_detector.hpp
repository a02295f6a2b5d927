#pragma once
// RaceDetector: finds, on a real run and with nothing added to the firmware,
// the races on every variable an interrupt handler shares with the main
// program:
//   - torn reads: a multi-byte read by the main program that an interrupt
//     splits between its bytes, by an ISR that writes the variable;
//   - torn writes: a multi-byte store by the main program split by an ISR
//     that reads the variable;
//   - stale reads: the main program spins in a loop that can never see a
//     variable change, because the compiler keeps the variable in a register
//     (an ISR-shared global not declared volatile), while an ISR writes it.
// It replaces the watch of two named counters (issue 6) by a search over
// every SRAM variable of the ELF (hil/data_objects.hpp).
//
// Signals:
//   in  avr_get_interrupt_irq(avr, v)[AVR_INT_IRQ_RUNNING] of every vector:
//       1 = entry, 0 = RETI
//   reads SP, the return address on the stack, the registers, flash, SRAM
//       (avr->data, no side effects)
//   uses AvrCore::set_step_watch while an ISR runs
//
// How (checked against simavr 1.6, sim_interrupts.c / sim_core.c):
//   1. Who shares what. While an ISR runs (entry to RETI, nested ones
//      included) every instruction is decoded before it executes
//      (AvrCore::set_step_watch: ISRs are ~1 % of the cycles, so stepping
//      them costs little); each load and store (LDS/STS, LD/ST X/Y/Z with
//      +/-, LDD/STD) is resolved with the registers of that moment and
//      attributed to the variable holding the address and to the vector.
//      This sees through attachInterrupt's ICALL and any helper the ISR calls.
//   2. Splits. simavr takes an interrupt only between instructions and
//      pushes the return word address (high byte at SP+1, low at SP+2). At
//      each entry that interrupts the main program the code around the
//      return address is decoded, backwards (what just ran) and forwards
//      (what runs after RETI), over consecutive loads (and, separately,
//      consecutive stores) only, each walk stopping at another instruction,
//      at a second access to an address it has already seen, at a pointer
//      it no longer knows, or after kMaxWalk instructions. A variable of 2..8
//      bytes with bytes accessed on both sides is split.
//      - A split read: its bytes are copied at entry and again at RETI; what
//        the main program gets is the bytes loaded before from the entry
//        copy and the others from the RETI copy. It is torn when the ISR
//        changed the variable, and a torn value is observed when what the
//        main program gets equals neither copy: a value the variable never
//        held (a 32-bit counter read low byte first tears visibly only when
//        an increment carries into a byte still to load).
//      - A split write: the value being written is the bytes already stored
//        and, for the bytes still to store, the registers that hold them.
//        It is torn when the ISR reads the variable before RETI, and a torn
//        value is observed when what the ISR read differs from the value
//        being written (the old bytes are gone, so whether the ISR's value
//        equals the old value is not known).
//      An access is identified by the address of its first instruction; it
//      is a race when a vector that splits it writes the variable (a read)
//      or reads it (a write) at some time in the run: "observed" when a torn
//      value was seen, else "possible".
//   3. Stale reads. At each entry that interrupts the main program the code
//      from the return address is checked (once per address): is it a loop
//      (a backward branch or jump within kMaxLoop instructions) whose body
//      reads no data memory and calls nothing, so that nothing an ISR does
//      can end it; and does a register loaded from a variable (LDS) just
//      before the loop reach the loop's test, or the skip or branch that
//      enters the loop, unchanged (a backward dependency walk over
//      straight-line code), and is it never written in the body. If so, and the ISR writes that
//      variable, the write is one the main program cannot see: a stale
//      read. Without volatile, avr-gcc turns `while (!flag) {}` into one
//      LDS, a test and an endless `rjmp .-2`; with volatile the LDS is
//      inside the loop and nothing is reported.
//
// It misses (by design): reads or writes whose bytes are spread over other
// instructions (arithmetic between the loads, a byte-wise loop), splits by
// a second interrupt during the same ISR entry, variables of more than 8
// bytes (arrays and structs: their elements are accessed separately),
// accesses never split in the run, and stale values kept in registers in
// code that is not a register-only loop. Callbacks do not allocate beyond
// the capacity reserved at construction (later records are counted as
// dropped), except one cache entry per distinct resume address, and never
// throw. Construct after the AvrCore and destroy before.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <unordered_map>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/cycle_time.hpp"
#include "hil/data_objects.hpp"
#include "hil/elf_image.hpp"
#include "hil/function_map.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// Pointer registers X, Y, Z (data-space values).
struct PointerRegs {
    uint16_t x = 0, y = 0, z = 0;
};

/// One load or store met by a walk around a resume address.
struct WalkAccess {
    uint16_t address = 0;  ///< data-space address
    uint32_t pc = 0;       ///< flash byte address of the instruction
    uint8_t reg = 0;       ///< Rd of a load, Rr of a store
    bool before = false;   ///< ran before the resume address (else: runs after it)
};

/// The consecutive loads (stores = false) or stores around `resume_pc`, as
/// described in the header: the backward walk first (nearest first), then
/// the forward walk.
std::vector<WalkAccess> walk_accesses(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs, bool stores);

/// The bytes of [address, address + size) loaded before / after `resume_pc`.
struct ReadSplit {
    uint8_t before = 0;  ///< bit i: byte i loaded by the instructions just before
    uint8_t after = 0;   ///< bit i: byte i loaded by the instructions from the resume address
    bool split() const { return before != 0 && after != 0; }
};
ReadSplit find_read_split(const AvrCore& core, uint32_t resume_pc, const PointerRegs& regs, uint16_t address,
                          uint16_t size);

/// A register-only loop the main program cannot leave on an ISR's write,
/// and the variable whose value it keeps in a register (exposed for tests).
struct StaleLoop {
    std::size_t object = 0;   ///< DataObjects index
    uint32_t load_pc = 0;     ///< the LDS that loaded it
    uint8_t reg = 0;          ///< the register it stays in
    uint32_t loop_begin = 0;  ///< first instruction of the loop (branch target)
    uint32_t loop_end = 0;    ///< the backward branch or jump
};
std::optional<StaleLoop> find_stale_loop(const AvrCore& core, const DataObjects& objects, uint32_t resume_pc);

enum class AccessKind { kRead, kWrite };

/// A multi-byte access of the main program that interrupts split.
struct SplitAccess {
    std::size_t object = 0;          ///< DataObjects index
    AccessKind kind = AccessKind::kRead;
    uint32_t pc = 0;                 ///< flash byte address of its first instruction
    std::array<uint64_t, kMaxVectors> splits{};  ///< per splitting vector
    uint64_t torn = 0;       ///< read: the ISR changed it; write: the ISR read it mid-write
    uint64_t observed = 0;   ///< torn with a value the main program (read) or ISR (write) should never see
    Cycles first_cycle = 0;  ///< entry of the ISR that first split it
    /// The first observed torn value: read: the entry copy, what the main
    /// program got, the RETI copy; write: -, what the ISR read, the value
    /// being written.
    uint64_t example_before = 0, example_seen = 0, example_after = 0;
    uint64_t total_splits() const;
};

/// A stale read seen on the run.
struct StaleRead {
    StaleLoop where;
    uint64_t writes_missed = 0;  ///< ISR entries that wrote the variable while main spun in the loop
    VectorMask vectors = 0;      ///< bit v: the vectors that wrote it
    Cycles first_cycle = 0;
};

/// An SRAM variable an ISR accessed.
struct SharedVariable {
    std::size_t object = 0;
    VectorMask isr_writers = 0;  ///< bit v: vector v's ISR stored into it
    VectorMask isr_readers = 0;  ///< bit v: vector v's ISR loaded from it
};

struct RaceStats {
    uint64_t entries_checked = 0;  ///< ISR entries that interrupted the main program
    uint64_t dropped = 0;          ///< split accesses past the record capacity
};

class RaceDetector {
public:
    static constexpr int kMaxWalk = 16;   ///< instructions decoded each way
    static constexpr int kMaxLoop = 32;   ///< instructions a stale loop may span
    static constexpr int kMaxNesting = 8;
    static constexpr std::size_t kMaxVariableBytes = 8;

    explicit RaceDetector(AvrCore& core, const ElfImage& elf, std::size_t record_capacity = 1024);
    ~RaceDetector();
    RaceDetector(const RaceDetector&) = delete;
    RaceDetector& operator=(const RaceDetector&) = delete;

    const DataObjects& objects() const { return objects_; }
    /// The chip it watches (vector names for reports).
    const McuDescription& mcu() const { return core_.mcu(); }
    /// Every variable an ISR loaded or stored, by address.
    std::vector<SharedVariable> shared() const;
    /// Every split access (races and splits by ISRs that do not share the
    /// variable alike), in the order first seen.
    const std::vector<SplitAccess>& splits() const { return accesses_; }
    /// True if `a` is a race: split by a vector that writes (read) or reads
    /// (write) the variable.
    bool is_race(const SplitAccess& a) const;
    /// Splits of `a` by such vectors.
    uint64_t race_splits(const SplitAccess& a) const;
    const std::vector<StaleRead>& stale_reads() const { return stale_; }
    const RaceStats& stats() const { return stats_; }
    /// True if flash byte address `pc` ran inside an ISR.
    bool ran_in_isr(uint32_t pc) const;
    /// The LDS (stores = false) or STS instructions of the main program that
    /// access `object` (instructions in `functions` that never ran inside an
    /// ISR), by flash byte address.
    std::vector<uint32_t> main_sites(std::size_t object, bool stores, const FunctionMap& functions) const;

private:
    struct Hook {
        RaceDetector* self = nullptr;
        int vector = 0;
        avr_irq_t* irq = nullptr;
    };
    struct Pending {
        std::size_t object = 0;
        AccessKind kind = AccessKind::kRead;
        uint32_t pc = 0;
        uint8_t before_mask = 0;             ///< bytes accessed before the entry
        std::array<uint8_t, kMaxVariableBytes> bytes{};  ///< read: at entry; write: the value being written
        bool isr_read = false;               ///< write: the ISR read it
        bool seen_differs = false;           ///< write: what the ISR read differs from the value being written
        uint64_t seen = 0;
    };

    static void on_running(avr_irq_t* irq, uint32_t value, void* param);
    static void on_step(void* self);
    void enter(int vector);
    void leave(int vector);
    void step();
    void entry_from_main();
    void finish_entry(int vector);
    SplitAccess* record(std::size_t object, AccessKind kind, uint32_t pc);
    uint64_t value_of(std::size_t object) const;

    AvrCore& core_;
    DataObjects objects_;
    std::vector<Hook> hooks_;
    std::array<int, kMaxNesting> vectors_{};
    int depth_ = 0;
    uint64_t entry_serial_ = 0;            ///< counts entries from the main program
    Cycles entry_cycle_ = 0;               ///< of the entry in progress
    std::vector<VectorMask> isr_writers_;  ///< per object
    std::vector<VectorMask> isr_readers_;
    std::vector<uint64_t> written_in_;     ///< per object: entry_serial_ of its last ISR store
    std::vector<Pending> pending_;         ///< splits of the entry in progress
    std::optional<StaleLoop> pending_stale_;
    std::unordered_map<uint32_t, std::optional<StaleLoop>> loop_cache_;
    std::vector<SplitAccess> accesses_;
    std::vector<StaleRead> stale_;
    std::vector<uint64_t> isr_pcs_;        ///< bit per flash word: ran inside an ISR
    RaceStats stats_;
};

}  // namespace ddmr::hil
