#pragma once
// FunctionProfiler: an exact flat profile of the firmware from every executed
// instruction: per function (FunctionMap: ELF entry points, libgcc's and
// libm's float routines included) the calls, the self cycles and the
// inclusive cycles, for the whole run and for the control loop only.
//
// Model (AvrCore's instruction hook, so one instruction per step):
//   self      the cycles of each instruction (simavr's cycle delta over the
//             step) go to the function holding the instruction's address.
//             SLEEP's idle cycles go to the function that slept.
//   stack     a shadow call stack of frames {function, SP at entry,
//             interrupt?, tail?}, updated after each instruction:
//     - CALL/RCALL/ICALL/EICALL that pushed a return address (SP - 2) push a
//       frame for the target and count a call. `rcall .+0` (avr-gcc's way to
//       reserve two stack bytes) is not a call.
//     - RET/RETI pop every frame whose SP at entry is below the new SP (a
//       frame's SP at entry is the SP after its return address was pushed).
//       Only RET/RETI pop: a two-byte OUT to SPH:SPL passes through
//       intermediate values that would fake a return.
//     - An interrupt (the new PC is a vector slot 1..25, entered with the
//       return address pushed) pushes an interrupt frame for `__vectors`;
//       the vector's JMP then names the handler (the frame takes the
//       handler's name and the handler gets the call). simavr may take an
//       interrupt in the same step as a CALL or RET: the instruction's own
//       effect is applied first, with the return address read back from the
//       stack.
//     - Any other transfer (JMP/RJMP/IJMP, a branch, falling through)
//       into another function: back into a function of the current tail
//       group (the top frames down to the last one a call or interrupt
//       made, e.g. `__tablejump2__` IJMPs into a constructor and returns
//       through it) pops back to it; else a tail frame sharing the top's SP
//       at entry is pushed. Into the function's entry point it counts a
//       call (`__subsf3` falls into `__addsf3`, `__addsf3` jumps to
//       `__fp_round`). Into its middle it does not: libm's hand-written
//       code shares tails between routines (`__mulsf3x` branches to
//       `__mulsf3`'s zero result, `__fp_split3` into `__fp_splitA`'s
//       subnormal path); those are counted in mid_function_branches().
//     Invariant after every step: the top frame's function is the function
//     of the PC.
//   inclusive each instruction's cycles also go to every distinct function
//             on the stack from the top down to the innermost interrupt
//             frame: interrupt time is not charged to the interrupted code,
//             and a function twice on the stack (recursion) counts once.
//             The bottom frame is `__vectors` (the reset vector jumps to the
//             start-up code): its inclusive is the whole run outside
//             interrupts, plus the vector JMPs.
//   calls     frames pushed for the function: calls, tail transfers into
//             its entry point, interrupt handler entries.
//   edges     the call graph: a frame is pushed by an edge {caller, callee,
//             site}: the function of the frame below, the frame's function,
//             and the flash byte address of the CALL/RCALL/ICALL, jump or
//             last instruction before a fall-through that pushed it. The
//             root frame and interrupt frames have no caller (kNoCaller,
//             kNoSite: gprof's <spontaneous>). An edge counts the calls the
//             frame counted and, when the frame closes, the inclusive cycles
//             it added to its function: so for every function the sums over
//             its incoming edges are its calls and its inclusive cycles. The
//             edge of a frame is looked up when it is pushed (a per-site
//             cache, else a hash map), never per instruction.
//   words     self cycles per flash word (the instruction's address / 2),
//             so source lines can be looked up when the profile is written.
// Inclusive cycles cost O(1) per instruction: each interrupt nesting level
// counts the cycles executed at it, and a frame adds its level's growth to
// its function when it closes (open frames are settled at loop boundaries
// and when read).
// The stack holds at most `max_depth` frames (reserved up front; no
// allocation per instruction, only when a call edge is first seen). A push
// beyond it replaces the top frame and counts a stack overflow; the counts
// stay exact for self cycles but not for inclusive cycles and calls after
// that (0 overflows on the reference firmware: its shadow stack is at most 15
// frames deep in case 1).
//
// Scopes:
//   whole run     every instruction from construction (install before the
//                 first instruction for a complete stack) to now.
//   control loop  only the completed control-loop iterations of a
//                 LoopProfiler: from one return of its mark (delay()) to the
//                 next, counted from the first return after arm() (the
//                 reference run arms when the case byte is sent). Wire it with
//                 loop_profiler.set_iteration_listener(
//                     [&](bool c) { function_profiler.on_loop_boundary(c); }).
//                 Interrupts inside an iteration count in it.
//   compute       the control loop without its wait: only the cycles while
//                 no frame of the wait function (set_wait_function(): the
//                 loop mark, delay()) is on the shadow stack, in the same
//                 completed iterations; interrupts taken outside the wait
//                 count in it. Its total is the sum of LoopProfiler's
//                 compute() over the same iterations (from the mark's return
//                 to its next entry), but for an interrupt simavr takes in the
//                 same step as the CALL to the mark or the RET from it: here
//                 it goes to the side the stack is on (after the CALL: the
//                 wait; after the RET: compute), there to the other (the
//                 mark's first instruction, the caller's next one, had not
//                 run): case 1 differs in 4 of 1199 iterations, by one ISR
//                 each, 5 cycles in all. Self cycles per function and per
//                 word only: calls, inclusive cycles and edges are the
//                 control loop's.
//
// All execution must go through AvrCore::run_until(Cycles) while installed
// (the condition overload does not call hooks).

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/function_map.hpp"

namespace ddmr::hil {

struct FunctionCounts {
    uint64_t calls = 0;          ///< frames pushed for the function
    Cycles self_cycles = 0;      ///< cycles of its own instructions
    Cycles inclusive_cycles = 0; ///< self + callees, interrupts excluded
};

/// One edge of the call graph, from one call site (see the header comment).
struct CallEdge {
    static constexpr FunctionId kNoCaller = 0xFFFF;     ///< the root frame, interrupt entries
    static constexpr uint32_t kNoSite = 0xFFFFFFFF;     ///< no calling instruction
    FunctionId caller = kNoCaller;  ///< function of the frame below, or kNoCaller
    FunctionId callee = 0;          ///< function of the pushed frame
    uint32_t site = kNoSite;        ///< flash byte address of the instruction that pushed it
};

struct EdgeCounts {
    uint64_t calls = 0;           ///< frames pushed by the edge that counted a call
    Cycles inclusive_cycles = 0;  ///< what those frames added to the callee's inclusive
};

struct ProfileScope {
    Cycles cycles = 0;            ///< cycles observed in the scope
    Cycles interrupt_cycles = 0;  ///< of which inside interrupt frames (vector JMP included)
    uint64_t iterations = 0;      ///< control loop: completed iterations; whole run: 0
    std::vector<FunctionCounts> functions;  ///< indexed by FunctionId
    /// Indexed like FunctionProfiler::edges(); edges first seen after the
    /// scope's last update are absent (zero).
    std::vector<EdgeCounts> edges;
    /// Self cycles of the instruction at each flash word (byte address / 2).
    std::vector<Cycles> word_cycles;
};

class FunctionProfiler {
public:
    static constexpr std::size_t kDefaultMaxDepth = 64;

    /// Builds the function map of `core`'s firmware and installs itself as
    /// an instruction hook. `max_depth` >= 2 frames.
    explicit FunctionProfiler(AvrCore& core, std::size_t max_depth = kDefaultMaxDepth);
    ~FunctionProfiler();
    FunctionProfiler(const FunctionProfiler&) = delete;
    FunctionProfiler& operator=(const FunctionProfiler&) = delete;

    /// A LoopProfiler iteration boundary (see the header comment).
    void on_loop_boundary(bool completed);

    const FunctionMap& map() const { return map_; }
    /// Up to now (open frames' inclusive cycles included).
    ProfileScope whole_run() const;
    const ProfileScope& control_loop() const { return loop_; }
    /// The control loop outside the wait function (see the header comment;
    /// empty until set_wait_function()).
    const ProfileScope& compute() const { return compute_; }
    /// The function whose frames are the loop's wait (the loop mark). Call
    /// before the first loop boundary.
    void set_wait_function(FunctionId function);
    /// The wait function, if set.
    [[nodiscard]] bool has_wait_function() const { return wait_function_ != kNoWaitFunction; }

    /// Every call edge seen so far, in order of first use (ProfileScope::edges' index).
    const std::vector<CallEdge>& edges() const { return edges_; }

    /// Functions on the shadow stack now, bottom first.
    std::vector<FunctionId> call_stack() const;
    std::size_t max_depth_seen() const { return max_depth_seen_; }
    uint64_t stack_overflows() const { return overflows_; }
    /// Branches into the middle of another function (shared tails).
    uint64_t mid_function_branches() const { return mid_function_branches_; }

private:
    struct Frame {
        FunctionId function;
        uint16_t sp_at_entry;    ///< SP after the return address was pushed
        uint16_t level;          ///< interrupt frames at or below it (0 = main code)
        bool is_interrupt;       ///< made by an interrupt (the base of a context)
        bool is_tail;            ///< made by a jump or fall-through, shares the SP below
        bool counts_inclusive;   ///< first frame of its function in its context
        bool awaiting_handler;   ///< interrupt frame still in the vector table
        Cycles inclusive_start;  ///< level_cycles_[level] when it was pushed (or settled)
        uint32_t edge;           ///< index in edges_ of the edge that pushed it
    };

    void on_instruction();
    void update_stack(uint32_t prev_pc, uint16_t prev_sp, uint32_t pc, uint16_t sp);
    void push(FunctionId function, uint16_t sp_at_entry, bool is_interrupt, bool is_tail, bool count_call,
              uint32_t site);
    /// The index of edge {caller, callee, site}, added if new.
    uint32_t edge_index(FunctionId caller, FunctionId callee, uint32_t site);
    void pop_to(std::size_t depth);
    /// Adds a frame's cycles since its push to its function's inclusive.
    void close(const Frame& frame);
    /// close() for every open frame, restarting their counts from now.
    void settle_open_frames();
    void find_context_base();
    void set_inclusive_flag(std::size_t index);
    /// The stack after `site`'s instruction transferred control to `pc`.
    void follow_transfer(uint32_t site, uint32_t pc);

    AvrCore& core_;
    avr_t* avr_;
    FunctionMap map_;
    /// Flash word index mask (flash sizes are powers of two). A PC past the
    /// flash (simavr stops the run as crashed) only reads a wrapped entry.
    uint32_t word_mask_;
    uint32_t vector_slot_;  ///< bytes per interrupt vector
    uint32_t vectors_end_;  ///< first flash byte after the vector table
    uint16_t ram_end_;
    uint16_t return_bytes_;  ///< a CALL or an interrupt pushes this many (2: 16-bit PC, 3: 22-bit)
    /// True for the flash byte address of an interrupt vector other than RESET.
    bool is_interrupt_vector(uint32_t pc) const {
        return pc >= vector_slot_ && pc < vectors_end_ && pc % vector_slot_ == 0;
    }
    std::size_t max_depth_;
    std::vector<Frame> stack_;     ///< max_depth_ slots; depth_ in use
    std::size_t depth_ = 0;
    std::size_t context_base_ = 0; ///< index of the innermost interrupt frame, 0 if none
    std::size_t level_ = 0;        ///< the top frame's level
    /// Cycles executed at each interrupt nesting level: a frame's inclusive
    /// cycles are its level's growth while it is open (deeper levels are
    /// interrupts, not charged to it). O(1) per instruction.
    std::vector<Cycles> level_cycles_;
    std::vector<uint8_t> flow_;    ///< per flash word: other, return, call (decoded once)

    std::vector<CallEdge> edges_;
    std::unordered_map<uint64_t, uint32_t> edge_ids_;  ///< key: site << 32 | caller << 16 | callee
    std::vector<uint32_t> site_edge_;  ///< per flash word: the last edge pushed from it + 1 (0: none)

    /// Self cycles per flash word since the last loop boundary, and the
    /// words they touched: folded into loop_ at a completed boundary,
    /// dropped otherwise (O(words run) per boundary, not O(flash)).
    std::vector<Cycles> window_word_cycles_;
    std::vector<uint32_t> window_words_;
    /// The same for the compute scope: only while no wait frame is open.
    std::vector<Cycles> window_compute_word_cycles_;
    std::vector<uint32_t> window_compute_words_;
    Cycles window_compute_cycles_ = 0;
    Cycles window_compute_interrupt_cycles_ = 0;

    static constexpr FunctionId kNoWaitFunction = 0xFFFF;
    FunctionId wait_function_ = kNoWaitFunction;
    std::size_t wait_frames_ = 0;  ///< frames of wait_function_ on the shadow stack

    uint32_t last_pc_ = 0;
    uint16_t last_sp_ = 0;
    Cycles last_cycle_ = 0;

    ProfileScope whole_;
    ProfileScope loop_;
    ProfileScope compute_;
    std::vector<FunctionCounts> window_start_;  ///< whole_.functions at the open boundary
    std::vector<EdgeCounts> window_start_edges_;  ///< whole_.edges at the open boundary
    Cycles window_start_cycles_ = 0;
    Cycles window_start_interrupt_cycles_ = 0;
    bool window_open_ = false;

    std::size_t max_depth_seen_ = 0;
    uint64_t overflows_ = 0;
    uint64_t mid_function_branches_ = 0;
};

}  // namespace ddmr::hil
