#include "hil/fast_forward.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <algorithm>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/fast_forward_loop.hpp"
#include "hil/mcu.hpp"

// Stepping: the instructions fast-forward runs itself (a checked pass, the
// way to a loop's anchor) and what it shows the instruction hooks of the
// passes it skipped (hil/fast_forward.hpp).

namespace ddmr::hil {

bool FastForward::step_one(bool silent) {
    avr_->run_cycle_count = 1;
    avr_run(avr_);
    if (!silent) core_.run_instruction_hooks();
    // A watchdog reset (simavr swapped its run callback) is AvrCore's to
    // take; a stop a part asked for ends the stepping at this instruction.
    return avr_->state == cpu_Running && !core_.event_pending() && !core_.stop_requested();
}

FastForward::Verify FastForward::verify_pass(const Loop& loop) {
    for (std::size_t i = 0; i < loop.pcs.size(); ++i) {
        const uint32_t pc = avr_->pc;
        if (pc != loop.pcs[i]) return Verify::kLeft;
        if (loop.through_pointer[i]) {
            const StepAccess a = step_access(core_.flash_word(pc), core_.flash_word(pc + 2), cpu());
            const StepAccess& b = loop.accesses[i];
            if (a.count != b.count || !std::equal(a.address.begin(), a.address.begin() + a.count, b.address.begin())) {
                return Verify::kLeft;
            }
        }
        if (loop.checked_write[i] && !write_inert(pc)) return Verify::kNotInert;  // before it is made
        if (!step_one(/*silent=*/true)) return Verify::kLeft;
    }
    return avr_->pc == loop.info.anchor && core_.stack_pointer() == loop.sp ? Verify::kHeld : Verify::kLeft;
}

// Steps from a PC of the pass (with its SP) on along the pass to the anchor
// (from the anchor itself: a whole pass); stops where the run leaves it (a
// branch taken otherwise, an interrupt) or a stop is requested.
bool FastForward::walks_by_step(const Loop& loop) const {
    return core_.has_instruction_hooks() || loop.info.pass_cycles >= kSamplePeriod;
}

FastForward::Walk FastForward::walk_to_anchor(const Loop& loop, const bool& halt_a, const bool& halt_b,
                                              bool any_anchor) {
    const uint16_t sp = core_.stack_pointer();
    std::size_t i = 0;
    while (i < loop.pcs.size() && (loop.pcs[i] != avr_->pc || loop.sps[i] != sp)) ++i;
    if (i == loop.pcs.size()) return Walk::kNotOnPath;
    // A short pass (delay()'s) runs on in simavr batches when there are no
    // instruction hooks to show: cheaper than stepping. A long one (a kit
    // robot's loop()) is stepped: where the run leaves it (a line sensor
    // changed the path), another learned pass may start, and a batch would
    // run on past that point (measured: 5 % faster on case 1, 5 % slower on
    // line_follower_digital with batches for all).
    if (!walks_by_step(loop)) return run_to_anchor(loop, i, halt_a, halt_b);
    // With `any_anchor`, the walk ends at the first PC on the way where a
    // loop that may jump is anchored with this SP (a long pass has dozens:
    // each PC a batch ended at was learned as one).
    avr_->run_cycle_limit = 1;
    for (; i < loop.pcs.size(); ++i) {
        if (avr_->pc != loop.pcs[i] || !step_one() || halt_a || halt_b) break;
        if (any_anchor && i + 1 < loop.pcs.size() && may_jump_here()) {
            avr_->run_cycle_limit = core_.free_run_limit();
            return Walk::kAtAnchor;
        }
    }
    avr_->run_cycle_limit = core_.free_run_limit();
    const bool arrived = i == loop.pcs.size() && avr_->state == cpu_Running && !halt_a && !halt_b &&
                         avr_->pc == loop.info.anchor && core_.stack_pointer() == loop.sp;
    return arrived ? Walk::kArrived : Walk::kLeft;
}

// With nothing to show each instruction to, the rest of the pass from step
// `i` runs in simavr batches, as a free run runs it: each ends at the next
// cycle timer (run there) or the pass's end, sooner at an interrupt. Where
// one ends, the run must be at the step the pass has at that cycle.
FastForward::Walk FastForward::run_to_anchor(const Loop& loop, std::size_t i, const bool& halt_a, const bool& halt_b) {
    const Cycles pass = loop.step_ends.back();
    const Cycles start = avr_->cycle - (i == 0 ? 0 : loop.step_ends[i - 1]);  // the pass's start
    for (;;) {
        const Cycles rest = start + pass - avr_->cycle;
        const avr_cycle_timer_slot_t* next = avr_->cycle_timers.timer;
        avr_->run_cycle_count = next == nullptr ? rest : next->when > avr_->cycle ? std::min(rest, next->when - avr_->cycle) : 1;
        avr_run(avr_);
        if (avr_->state != cpu_Running || halt_a || halt_b || core_.event_pending() || core_.stop_requested()) {
            return Walk::kLeft;
        }
        const Cycles done = avr_->cycle - start;
        const uint16_t sp = core_.stack_pointer();
        if (done == pass) return avr_->pc == loop.info.anchor && sp == loop.sp ? Walk::kArrived : Walk::kLeft;
        const auto at = std::lower_bound(loop.step_ends.begin(), loop.step_ends.end(), done);
        if (at == loop.step_ends.end() || *at != done) return Walk::kLeft;
        const auto j = static_cast<std::size_t>(at - loop.step_ends.begin()) + 1;
        if (loop.pcs[j] != avr_->pc || loop.sps[j] != sp) return Walk::kLeft;
    }
}

void FastForward::set_stack_pointer(uint16_t sp) {
    avr_->data[mcu_.spl] = static_cast<uint8_t>(sp & 0xFFU);
    if (mcu_.sph != 0) avr_->data[mcu_.sph] = static_cast<uint8_t>(sp >> 8);
}

// One pass from `start`, instruction by instruction: the PC, SP and cycle
// after each, then `show`.
template <typename Show>
void FastForward::show_pass(const Loop& loop, Cycles start, const Show& show) {
    const std::size_t n = loop.pcs.size();
    for (std::size_t i = 0; i < n; ++i) {
        const bool last = i + 1 == n;
        avr_->pc = last ? loop.info.anchor : loop.pcs[i + 1];
        set_stack_pointer(last ? loop.sp : loop.sps[i + 1]);
        avr_->cycle = start + loop.step_ends[i];
        show();
    }
}

// The instruction hooks see each instruction of the `passes` passes from
// `now` (the skipped ones and the verification pass) as stepping shows it:
// after it, with the next PC, the SP and the cycle of its end. The hooks
// read nothing else (AvrCore::HookReads::kPcSpCycle). A hook that counts
// its state's changes is shown the first pass, and the others only if that
// one changed its state (AvrCore::add_instruction_hook).
void FastForward::replay_to_hooks(const Loop& loop, Cycles now, Cycles passes) {
    const std::vector<AvrCore::InstructionHook>& hooks = core_.instruction_hooks();
    if (hooks.empty() || passes == 0) return;
    const Cycles end = avr_->cycle;
    std::vector<uint64_t> before(hooks.size());
    for (std::size_t h = 0; h < hooks.size(); ++h) before[h] = hooks[h].state_changes ? hooks[h].state_changes() : 0;
    show_pass(loop, now, [&] { core_.run_instruction_hooks(); });
    std::vector<const AvrCore::InstructionHook*> every_pass;
    for (std::size_t h = 0; h < hooks.size(); ++h) {
        if (!hooks[h].state_changes || hooks[h].state_changes() != before[h]) every_pass.push_back(&hooks[h]);
    }
    for (Cycles j = 1; j < passes && !every_pass.empty(); ++j) {
        show_pass(loop, now + j * loop.info.pass_cycles, [&] {
            for (const AvrCore::InstructionHook* h : every_pass) h->hook();
        });
    }
    avr_->pc = loop.info.anchor;
    set_stack_pointer(loop.sp);
    avr_->cycle = end;
}

}  // namespace ddmr::hil
