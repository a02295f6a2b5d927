#pragma once
// IsrMonitor: per-vector interrupt timing on a running AvrCore, with nothing
// added to the firmware ("debug ISR timing", issue 6).
//
// Signals (simavr 1.6, sim_interrupts.c), for every vector 1..25:
//   in  avr_get_interrupt_irq(avr, v)[AVR_INT_IRQ_PENDING]  1 = raised (flag set
//       by its source), 0 = cleared (taken, or the flag written off)
//   in  avr_get_interrupt_irq(avr, v)[AVR_INT_IRQ_RUNNING]  1 = the vector is
//       entered (return address pushed, I cleared, PC = vector), 0 = its RETI
//   in  (precise mode) a 1-cycle cycle timer that reads SREG.I after every
//       instruction
//
// What is measured, in AVR cycles (the AVR clock as simavr counts it):
//   latency   = entry - raise: the cycle the vector's first instruction (its
//               JMP) starts minus the cycle simavr raised the interrupt. simavr
//               raises an interrupt from the source's callback, which runs
//               after the instruction in progress, so an event that falls
//               inside a multi-cycle instruction is stamped at its end. For
//               INT0/INT1 fed by the EncoderInjector the raise is the cycle the
//               edge is put on the pin. simavr charges no interrupt-response
//               cycles (the datasheet's 4, atmega328p::
//               kDatasheetInterruptResponseCycles): with I set and nothing else
//               pending the latency is 0 if the raise falls on an instruction
//               boundary. After SEI or RETI simavr runs two more instructions
//               before it takes an interrupt (the datasheet says one).
//   duration  = end of RETI - entry: the JMP in the vector table, the handler
//               and its RETI (McuDescription::reti_cycles, added because simavr
//               reports the RETI before charging its cycles). It includes any
//               ISR that nested inside (only if the handler re-enabled I).
//   cpu_share = sum of durations / cycles observed since construction.
//   isr_cycles = cycles with at least one ISR running (nested time once).
//   interrupts_disabled_cycles (precise mode only) = cycles executed with
//               SREG.I clear: ISRs plus the main code's cli/SREG-restore
//               sections. simavr has no hook for CLI/SEI (they are not data
//               writes), so the only exact way is to look at I after every
//               instruction: `precise` arms a cycle timer that fires after
//               each instruction (the run then goes instruction by
//               instruction, several times slower). Without it the summary
//               leaves the field empty and isr_cycles is the lower bound.
//
// A vector entered while it is already running (its handler set I and the
// same source fired again) is counted as a re-entry and timed on its own;
// nesting deeper than kMaxNesting is counted and not timed.
//
// Callbacks never allocate (the optional event log is reserved up front and
// stops recording when full) and never throw. Construct the monitor after the
// AvrCore and destroy it before; it unregisters its hooks when destroyed.
// Not thread-safe (like AvrCore).

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hil/atmega328p.hpp"
#include "hil/avr_core.hpp"
#include "hil/cycle_time.hpp"
#include "hil/elf_image.hpp"

struct avr_irq_t;

namespace ddmr::hil {

struct IsrMonitorConfig {
    /// Account SREG.I after every instruction (exact interrupts-disabled time,
    /// the run is several times slower). Default off.
    bool precise = false;
    /// Per-entry records to keep (IsrMonitor::events()); 0 keeps none. Reserved
    /// at construction; entries past it are timed but not recorded.
    std::size_t event_capacity = 0;
};

/// Fixed power-of-two bins for cycle counts: bin 0 holds 0, bin k in
/// 1..kBins-2 holds [2^(k-1), 2^k), the last bin holds everything from
/// 2^(kBins-2) = 65,536 cycles (4.1 ms at 16 MHz) up.
struct CycleHistogram {
    static constexpr std::size_t kBins = 18;
    std::array<uint64_t, kBins> counts{};

    static std::size_t bin_of(Cycles cycles);
    /// Smallest value of the bin.
    static Cycles lower_bound(std::size_t bin);
    /// "0", "1", "2-3", ..., "32768-65535", ">=65536".
    static std::string label(std::size_t bin);
    void add(Cycles cycles) { ++counts[bin_of(cycles)]; }
};

/// count, min, max and sum of a series of cycle counts.
struct CycleStats {
    uint64_t count = 0;
    Cycles min = 0;
    Cycles max = 0;
    Cycles sum = 0;
    double mean() const { return count == 0 ? 0.0 : static_cast<double>(sum) / static_cast<double>(count); }
    void add(Cycles cycles);
};

/// One ISR entry (IsrMonitorConfig::event_capacity > 0).
struct IsrEvent {
    int vector = 0;
    std::optional<Cycles> raise_cycle;  ///< empty if the raise was not seen
    Cycles entry_cycle = 0;             ///< the vector's JMP starts
    std::optional<Cycles> exit_cycle;   ///< end of RETI; empty while running
};

struct VectorSummary {
    int vector = 0;        ///< 1..25, datasheet table 12-6
    std::string name;      ///< table 12-6 source name, e.g. "INT0", "TIMER0_OVF"
    std::string handler;   ///< ELF function the vector's JMP reaches, e.g. "__vector_1"
    uint64_t count = 0;    ///< entries
    uint64_t raised = 0;   ///< raises simavr reported (none while already pending)
    uint64_t reentries = 0;  ///< entries while the same vector was running
    CycleStats latency;    ///< [cycles] entries whose raise was seen
    CycleStats duration;   ///< [cycles] completed entries, JMP to end of RETI
    CycleHistogram latency_histogram;
    CycleHistogram duration_histogram;
    double cpu_share = 0.0;  ///< duration.sum / observed cycles, 0..1
};

struct IsrSummary {
    Cycles start_cycle = 0;  ///< when the monitor started
    Cycles end_cycle = 0;    ///< when the summary was taken
    uint32_t clock_hz = 0;   ///< the board's clock
    Cycles observed_cycles() const { return end_cycle - start_cycle; }
    Cycles isr_cycles = 0;   ///< cycles with any ISR running (nested once)
    /// Cycles with SREG.I clear; only in precise mode.
    std::optional<Cycles> interrupts_disabled_cycles;
    bool precise = false;
    int max_nesting = 0;           ///< deepest ISR nesting seen
    uint64_t untimed_entries = 0;  ///< entries past kMaxNesting
    std::vector<VectorSummary> vectors;  ///< vectors entered at least once, by number
    /// Vectors whose flag was raised but that were never entered (interrupt
    /// not enabled: e.g. Timer1/Timer2 overflow flags under Arduino's PWM).
    std::vector<std::string> raised_not_entered;
};

/// The summary as markdown: one table row per vector (count, latency and
/// duration min/mean/max in cycles, CPU share in %), the totals, and a second
/// table with the non-empty histogram bins.
std::string to_markdown(const IsrSummary& summary);

/// The ELF function vector `vector`'s JMP (or RJMP) reaches: its handler, e.g.
/// "__vector_1"; kNoHandler for a vector the firmware does not use; "?" when
/// the vector slot is not a jump; the address when no symbol covers it.
std::string vector_handler_name(const AvrCore& core, const ElfImage& elf, int vector);
/// avr-libc's target of the vectors without a handler.
inline constexpr const char* kNoHandler = "__bad_interrupt";

class IsrMonitor {
public:
    static constexpr int kMaxNesting = 8;

    /// Hooks every vector's PENDING and RUNNING IRQs of `core`; `elf` names
    /// the handlers. Throws std::runtime_error if simavr lacks a vector's IRQs.
    IsrMonitor(AvrCore& core, const ElfImage& elf, const IsrMonitorConfig& config = {});
    ~IsrMonitor();
    IsrMonitor(const IsrMonitor&) = delete;
    IsrMonitor& operator=(const IsrMonitor&) = delete;

    /// Totals up to the current cycle (ISRs still running are not in the
    /// durations; their time so far is in isr_cycles).
    IsrSummary summary() const;
    const std::vector<IsrEvent>& events() const { return events_; }
    /// Cycle of the latest raise of `vector` not yet taken, if any.
    std::optional<Cycles> pending_since(int vector) const;

private:
    struct Hook {
        IsrMonitor* self = nullptr;
        int vector = 0;
    };
    struct Frame {
        Cycles entry = 0;
        std::size_t event = 0;  ///< index in events_, or kNoEvent
    };
    struct VectorState {
        avr_irq_t* irqs = nullptr;  ///< [AVR_INT_IRQ_PENDING], [AVR_INT_IRQ_RUNNING]
        Hook hook;
        std::optional<Cycles> raise;
        uint64_t count = 0;
        uint64_t raised = 0;
        uint64_t reentries = 0;
        CycleStats latency;
        CycleStats duration;
        CycleHistogram latency_histogram;
        CycleHistogram duration_histogram;
        std::array<Frame, kMaxNesting> frames{};
        int depth = 0;
    };
    static constexpr std::size_t kNoEvent = static_cast<std::size_t>(-1);

    static void on_pending(avr_irq_t* irq, uint32_t value, void* param);
    static void on_running(avr_irq_t* irq, uint32_t value, void* param);
    static uint64_t on_instruction(struct avr_t* avr, uint64_t when, void* param);
    void enter(VectorState& v, int vector);
    void leave(VectorState& v);

    AvrCore& core_;
    IsrMonitorConfig config_;
    Cycles start_cycle_ = 0;
    const McuDescription& mcu_;
    std::vector<VectorState> vectors_;  ///< per vector of the MCU (never resized: hooks point into it)
    std::vector<std::string> handlers_;
    std::vector<IsrEvent> events_;
    int nesting_ = 0;  ///< ISRs running now, all vectors
    int max_nesting_ = 0;
    uint64_t untimed_ = 0;
    Cycles isr_cycles_ = 0;
    Cycles outermost_entry_ = 0;
    // precise mode: the I flag that holds for the instruction starting at last_cycle_
    bool i_flag_ = false;
    Cycles last_cycle_ = 0;
    Cycles disabled_cycles_ = 0;
};

}  // namespace ddmr::hil
