#pragma once
// FastForward: skips whole passes of a firmware's busy-wait loops exactly
// (delay(), while (millis() < t), a poll of a flag an event sets), inside
// AvrCore's stepping loop, so every front end gets it.
//
// Detect: at the end of each instruction batch (at each cycle timer, and at
// least every kSamplePeriod cycles while fast-forward is on), a PC seen
// twice with the same SP in the last kHistory batch ends is a candidate
// anchor; a batch end inside a learned pass steps on along it to its anchor.
// A loop is learned per anchor and SP: the same code at another stack depth
// carries its bytes at other addresses. Two passes from it are stepped and
// recorded (hil/loop_pass.hpp); they must follow the same instruction path
// in the same cycles, touch only I/O whose reads have no side effects
// (plain registers, TCNTn, PINx), write I/O registers only with the value
// they hold where simavr's handling of that write changes nothing
// (fast_forward_write.cpp: PORTx, DDRx, TCCRnx, OCRnx), and leave every
// loop-carried byte as it found it. Otherwise the anchor is refused, with
// the reason. A PC the loop passes several times per period (digitalWrite()
// called four times by each pass of loop()) has passes that differ: the
// period is found, and the loop is learned from a PC it passes once.
//
// Jump: at an anchor, with no interrupt pending, the next cycle timer that
// may change what the loop reads or be observed (a timer that raises an
// interrupt, a UART/TWI/ADC/EEPROM completion, the plant's pin events, a
// run's target or stop) bounds the jump; timers that only set the flag of a
// disabled interrupt (Timer1/Timer2 in the Arduino core's phase-correct mode:
// hil/phase_correct_timer.hpp), of a timer the
// loop does not read, are held back and replayed in order after it, and the
// parts' steps that may run inside a jump (ReplayableTimer::kAtOwnCycle: the
// plant coupler's) run at their own cycles once it is verified. The state is
// saved, the clock moves k passes on, and one pass is stepped and checked
// against the learned path and carried bytes; on a mismatch the state is
// restored and the next try aims at half the distance (bisection toward the
// change of path). A loop whose path changes at a steady period (delay()'s
// milliseconds) is jumped to just before its next predicted change instead,
// and the passes around it run; the prediction only aims the jumps.
//
// Learning is in fast_forward_learn.cpp, jumps in fast_forward.cpp.
//
// Instruction hooks that read only the PC, SP and cycle (the profilers:
// AvrCore::HookReads::kPcSpCycle) see every instruction fast-forward steps,
// and every instruction of a skipped pass afterwards, with the PC, SP and
// cycle it had (replay_to_hooks): what they count is what stepping gives.
// A verification pass is shown only once it is kept. Not used while another
// instruction hook or a step watch is installed (gdb, the race detector
// inside an ISR). Not thread-safe (one per AvrCore).

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "hil/cycle_time.hpp"
#include "hil/loop_pass.hpp"
#include "hil/io_bit_use.hpp"
#include "hil/timer_event_reach.hpp"

struct avr_t;

namespace ddmr::hil {

class AvrCore;
struct McuDescription;

/// The parts watching one I/O register through simavr's memory IRQ, which
/// simavr raises on reads as on writes (AvrCore::watch_io).
struct IoWatchers {
    int count = 0;          ///< parts watching it
    int reads_matter = 0;   ///< those for which a read's notification changes something
};

/// A simavr cycle timer's callback (avr_cycle_timer_t).
using CycleTimerFn = uint64_t (*)(avr_t*, uint64_t, void*);

/// The passes a jump skips, as a cycle timer that asks to be replayed sees them.
struct LoopSpan {
    uint16_t min_sp = 0;  ///< the lowest SP before any instruction of a pass
    uint16_t max_sp = 0;  ///< the highest
    /// The lowest SRAM address a pass writes (0xFFFF: none; registers, SREG
    /// and SP are not SRAM).
    uint16_t lowest_sram_write = 0xFFFF;
    const std::vector<uint32_t>* pcs = nullptr;  ///< the PCs of a pass, in order
    std::vector<uint16_t> io_reads;  ///< the I/O data addresses a pass reads (sorted, unique)
    [[nodiscard]] bool reads(uint16_t address) const {
        return std::binary_search(io_reads.begin(), io_reads.end(), address);
    }
    std::vector<uint16_t> io_writes;  ///< the I/O data addresses a pass writes (sorted, unique)
    [[nodiscard]] bool writes(uint16_t address) const {
        return std::binary_search(io_writes.begin(), io_writes.end(), address);
    }
    /// Per PIN or TIFR register a pass reads: the bits whose value can change
    /// what it does (hil/io_bit_use.hpp). A register read and not listed: all.
    std::vector<IoBits> io_bits;
    /// True if the level of bit `bit` of the I/O register can change what a pass does.
    [[nodiscard]] bool reads_bit(uint16_t address, unsigned bit) const {
        if (!reads(address)) return false;
        const auto it = std::find_if(io_bits.begin(), io_bits.end(),
                                     [address](const IoBits& p) { return p.address == address; });
        return it == io_bits.end() || ((static_cast<unsigned>(it->used) >> bit) & 1U) != 0;
    }
    /// True if a pass writes no SRAM byte below its own stack (no global,
    /// no heap): what a part reads of the firmware's globals is the same at
    /// every cycle of the skipped passes.
    [[nodiscard]] bool writes_only_own_stack() const { return lowest_sram_write >= min_sp; }
};

/// A cycle timer of a part that does not bound a jump, when `may_replay`
/// says so for the passes skipped:
/// - kAfterJump: a sampler whose calls over such passes would change
///   nothing (a stack sampler, if the passes' SP stays above its limit); run
///   after the jump, in order.
/// - kAtOwnCycle: a part's step that reads of the firmware only what such
///   passes cannot change (the plant coupler: the driver pins' recorded
///   waveforms, globals). Run once the jump is verified (no I/O written, no
///   interrupt in it), at its own cycle (the core's clock set to it). It may
///   schedule cycle timers: if one falls inside the jump, the jump is taken
///   back and the run goes on from before it. A stop it requests is
///   deferred to its own cycle the same way.
struct ReplayableTimer {
    enum class Runs { kAfterJump, kAtOwnCycle };
    CycleTimerFn fn = nullptr;
    void* param = nullptr;
    std::function<bool(const LoopSpan&)> may_replay;
    Runs runs = Runs::kAfterJump;
};

/// One learned loop (an anchor PC and its pass).
struct SkippedLoop {
    uint32_t anchor = 0;             ///< flash byte address
    uint32_t pc_low = 0, pc_high = 0;  ///< the pass's PC range [low, high]
    std::vector<uint32_t> path;      ///< the pass's PCs, in order
    Cycles pass_cycles = 0;
    uint64_t skips = 0;              ///< jumps taken
    uint64_t cycles_skipped = 0;
    uint64_t mismatches = 0;         ///< verification passes that left the path
    uint64_t taken_back = 0;         ///< verified jumps undone: a part's step scheduled an event inside
};

/// An anchor that was refused, with the reason and how often the run came by it.
struct RefusedLoop {
    uint32_t anchor = 0;
    std::string reason;
    uint64_t visits = 0;
};

struct FastForwardStats {
    uint64_t cycles_skipped = 0;
    uint64_t skips = 0;
    uint64_t mismatches = 0;
    uint64_t taken_back = 0;
    std::vector<SkippedLoop> loops;
    std::vector<RefusedLoop> refused;
};

class FastForward {
public:
    /// `core`: the core it runs in (owns it). `replayable`: the parts'
    /// timers that need not bound a jump (owned by the caller, kept up to
    /// date). `watchers`: the parts' I/O watches by data address (likewise).
    FastForward(AvrCore& core, const std::vector<ReplayableTimer>& replayable,
                const std::unordered_map<uint16_t, IoWatchers>& watchers);
    ~FastForward();
    FastForward(const FastForward&) = delete;
    FastForward& operator=(const FastForward&) = delete;

    /// Called between instruction batches of a free run. May step
    /// instructions (learning) or jump; stops stepping as soon as `halt`
    /// turns true (the run's target reached, a stop requested) or the CPU
    /// leaves the running state. Returns true if it ran anything.
    bool after_batch(const bool& halt_a, const bool& halt_b);
    /// The longest instruction batch while fast-forward is on [cycles]: a
    /// loop's PCs come up at batch ends often enough to be found.
    static constexpr Cycles kSamplePeriod = 256;

    [[nodiscard]] FastForwardStats stats() const;

    /// While a jump runs the parts' steps at their own cycles (kAtOwnCycle),
    /// the held timers due inside it (kAfterJump: a part's pin edges) run
    /// after them: events may still arrive from this cycle on. A part that
    /// writes a time-ordered record (the VCD) closes it no later than this.
    /// kAllSettled outside such steps.
    [[nodiscard]] Cycles unsettled_from() const { return unsettled_from_; }
    static constexpr Cycles kAllSettled = ~Cycles{0};

private:
    struct Loop;
    struct ChangeTrack;
    struct Snapshot;
    enum : int32_t { kUnknown = -1 };
    /// after_batch at a PC that tells which loop and visit it is.
    bool look(const bool& halt_a, const bool& halt_b);
    bool learn(uint32_t anchor, const bool& halt_a, const bool& halt_b, bool seek_period = true);
    bool learn_period(const bool& halt_a, const bool& halt_b);
    /// How a recorded pass ended (kWrites: it was about to make an I/O write
    /// that is not inert, write_inert).
    enum class Record { kPass, kDiffers, kTooLong, kCut, kWrites };
    [[nodiscard]] std::string learning_refusal(Record r) const;
    /// `bits`, if given, follows which PIN bits the pass uses.
    Record record_pass(uint32_t anchor, std::vector<RecordedStep>& steps, Cycles& cycles,
                       const std::vector<RecordedStep>* follow, const bool& halt_a, const bool& halt_b,
                       IoBitUse* bits = nullptr);
    std::string accept_io(const PassAnalysis& analysis) const;
    // I/O writes (fast_forward_write.cpp).
    enum class WriteClass { kPlain, kPort, kTimerControl, kTimerCompare, kOther };
    [[nodiscard]] WriteClass write_class(uint16_t address) const;
    [[nodiscard]] bool write_inert(uint32_t pc) const;
    [[nodiscard]] bool port_write_inert(const void* port) const;
    [[nodiscard]] bool low_level_interrupt_at(char port, unsigned bit) const;
    [[nodiscard]] bool compare_write_inert(uint16_t address) const;
    [[nodiscard]] std::string accept_writes(const PassAnalysis& analysis) const;
    [[nodiscard]] bool io_observed(uint16_t address) const;
    [[nodiscard]] bool writes_checked_io(const StepAccess& access) const;
    struct Held;
    bool try_jump(Loop& loop);
    bool pass_runs_on_path(const Loop& loop);
    static void note_change(Loop& loop, Cycles at);
    Cycles aim_before_change(Loop& loop);
    static constexpr Cycles kNoChangeSeen = ~Cycles{0};
    /// kWaiting: on a learned pass whose anchor no jump could leave before
    /// the next event (nothing run: stepping to it would gain nothing).
    enum class Entered { kNo, kRan, kWaiting };
    Entered enter_learned_pass(const bool& halt_a, const bool& halt_b);
    [[nodiscard]] bool jump_may_follow(const Loop& loop) const;
    /// True if walk_to_anchor steps the loop's pass instruction by instruction.
    [[nodiscard]] bool walks_by_step(const Loop& loop) const;
    /// kAtAnchor: at another loop's anchor, from which it may jump.
    enum class Walk { kNotOnPath, kLeft, kArrived, kAtAnchor };
    Walk walk_to_anchor(const Loop& loop, const bool& halt_a, const bool& halt_b, bool any_anchor = false);
    /// The loop anchored at the PC with the SP, if one is and it is not refused (else nullptr).
    [[nodiscard]] Loop* loop_here();
    [[nodiscard]] bool may_jump_here() { return loop_here() != nullptr; }
    Walk run_to_anchor(const Loop& loop, std::size_t i, const bool& halt_a, const bool& halt_b);
    enum class Jump { kTooShort, kMismatch, kTakenBack, kStopDeferred, kSkipped };
    Jump jump_once(Loop& loop, Cycles now, Cycles cap, Cycles& changes_by);
    enum class Verify { kHeld, kLeft, kNotInert };
    Verify verify_pass(const Loop& loop);
    /// Steps one instruction; shows it to the instruction hooks unless `silent`
    /// (a verification pass, which may be taken back).
    bool step_one(bool silent = false);
    void replay_to_hooks(const Loop& loop, Cycles now, Cycles passes);
    template <typename Show>
    void show_pass(const Loop& loop, Cycles start, const Show& show);
    void set_stack_pointer(uint16_t sp);
    bool carried_unchanged(const Loop& loop, const Snapshot& before) const;
    Snapshot snapshot();
    void restore(const Snapshot& before);
    std::vector<Held> hold_timers(const Loop& loop, Cycles end);
    bool run_own_cycle_timers(const Loop& loop, std::vector<Held>& held, Cycles now, Cycles end, Cycles& stop_at);
    static Cycles fires_at(const Loop& loop, Cycles now, Cycles when);
    void release(const Loop& loop, const std::vector<Held>& held, Cycles now);
    Cycles bound(const Loop& loop) const;
    /// How a pending cycle timer stands to a jump over the loop's passes.
    enum class Defer { kNo, kReplay, kAtOwnCycle };
    /// `when`: the cycle the timer is due at.
    Defer deferrable(CycleTimerFn fn, const void* param, Cycles when, const Loop& loop) const;
    bool still_deferred(const Loop& loop, const std::vector<Held>& held, Cycles end) const;
    bool registered(CycleTimerFn fn, const void* param) const;
    void refuse(uint32_t anchor, uint16_t sp, std::string reason);
    /// The loop (or refusal) anchored at `pc` for stack pointer `sp`, or kUnknown.
    [[nodiscard]] int32_t loop_for(uint32_t pc, uint16_t sp) const;
    /// Adds a loop (or a refusal) to loops_, chained at its anchor's PC.
    void link(Loop&& loop);
    int32_t& slot(uint32_t pc) { return state_[pc >> 1]; }
    CpuView cpu() const;

    AvrCore& core_;
    avr_t* avr_;
    const McuDescription& mcu_;
    const std::vector<ReplayableTimer>& replayable_;
    const std::unordered_map<uint16_t, IoWatchers>& watchers_;
    std::vector<int32_t> state_;  ///< per flash word: kUnknown, the first loop anchored there (Loop::next_at_pc), or -2 - refusal index
    std::vector<int32_t> path_;   ///< per flash word: a loop whose pass runs through it (not its anchor), or kUnknown
    /// The first loop whose pass runs through a PC with an SP (pass_key), not at its anchor.
    std::unordered_map<uint64_t, int32_t> on_pass_;
    static uint64_t pass_key(uint32_t pc, uint16_t sp) { return uint64_t{pc} << 16 | sp; }
    std::vector<Loop> loops_;
    std::vector<RefusedLoop> refused_;
    std::vector<void*> timers_;  ///< simavr's timer modules (their cycle timers' parameter)
    std::vector<TimerEventReach> timer_reach_;  ///< per timer module, in timers_'s order
    std::vector<void*> ports_;   ///< simavr's I/O port modules (avr_ioport_t)
    /// The I/O registers whose bits a pass's use is followed in (IoBitUse):
    /// the PINx and the timers' TIFRn; their reads have no side effects.
    std::vector<uint16_t> followed_registers_;
    /// PCs (pass_key) that a learned pass runs through more than once: no
    /// walk from there (which visit?), and no learning either.
    std::unordered_set<uint64_t> ambiguous_;
    uint16_t not_inert_ = 0;  ///< the register of the last write record_pass found not inert
    static constexpr unsigned kHistory = 32;  ///< batch-end PCs kept to find one that comes back
    uint32_t last_pc_[kHistory] = {};
    uint16_t last_sp_[kHistory] = {};
    unsigned last_next_ = 0;
    Cycles no_learning_before_ = 0;
    Cycles no_jump_before_ = 0;
    uint64_t cycles_skipped_ = 0;
    Cycles unsettled_from_ = kAllSettled;
    std::vector<uint8_t> saved_data_;
    std::unordered_map<uint64_t, int> tries_;  ///< learning attempts that failed, by anchor << 16 | SP
};

}  // namespace ddmr::hil
