#include "hil/fast_forward.hpp"

#include <avr_ioport.h>
#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_regbit.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <limits>

#include "hil/avr_core.hpp"
#include "hil/avr_decode.hpp"
#include "hil/mcu.hpp"
#include "hil/simavr_io.hpp"

namespace ddmr::hil {
namespace {

/// A pass longer than this is not a busy-wait loop worth skipping.
constexpr std::size_t kMaxPassSteps = 400;
constexpr Cycles kMaxPassCycles = 2000;
/// Fewer passes than this per jump do not pay for the verification pass.
constexpr Cycles kMinPassesPerJump = 1;
/// After a learning attempt an interrupt or a stop cut short.
constexpr Cycles kLearningBackoff = 4096;
/// Passes that twice left their path before it repeated: refused after this many tries.
constexpr int kMaxLearningTries = 16;
/// Cycles kept between a verification pass's end and the bound: an
/// instruction that leaves the path may take more cycles than on the
/// learned pass (a skip, a taken branch: at most a 5-cycle RET/CALL more),
/// and must still end before the bound's timer, which could raise an
/// interrupt the restore cannot take back.
constexpr Cycles kVerifyMargin = 5;
/// Jumps tried in a row at one anchor (bisection toward a change of path,
/// retries up to an event a part's step scheduled).
constexpr int kMaxJumpAttempts = 12;

/// True if something listens to the I/O address's memory IRQs (raised on reads too).
bool has_listeners(const avr_t* avr, uint16_t address) {
    const avr_irq_t* irq = avr->io[AVR_DATA_TO_IO(address)].irq;
    if (irq == nullptr) return false;
    for (int i = 0; i <= AVR_IOMEM_IRQ_ALL; ++i) {
        if (irq[i].hook != nullptr) return true;
    }
    return false;
}

/// True if a read of the address is seen by a part: a listener that did not
/// declare itself through AvrCore::watch_io, or one whose state a read's
/// notification can change.
bool read_observed(const avr_t* avr, const std::unordered_map<uint16_t, IoWatchers>& watchers, uint16_t address) {
    if (!has_listeners(avr, address)) return false;
    const auto it = watchers.find(address);
    return it == watchers.end() || it->second.reads_matter > 0;
}

/// True if simavr's SREG arrays agree on the flags in `mask`.
bool flags_equal(uint8_t mask, const uint8_t* a, const uint8_t* b) {
    for (unsigned f = 0; f < 8; ++f) {
        if (((mask >> f) & 1U) != 0 && (a[f] != 0) != (b[f] != 0)) return false;
    }
    return true;
}

/// A register's name for a refusal, from the MCU description where it has one.
std::string io_name(const McuDescription& mcu, uint16_t a) {
    for (const PortRegisters& p : mcu.ports) {
        if (a == p.pin) return fmt::format("PIN{}", p.port);
        if (a == p.ddr) return fmt::format("DDR{}", p.port);
        if (a == p.port_register) return fmt::format("PORT{}", p.port);
    }
    for (const UsartDesc& u : mcu.usarts) {
        if (a == u.udr) return fmt::format("UDR{}", u.index);
        if (a == u.ucsra) return fmt::format("UCSR{}A", u.index);
        if (a == u.ucsrb) return fmt::format("UCSR{}B", u.index);
    }
    for (const TimerDesc& t : mcu.timers) {
        if (a == t.tcnt_low || (t.tcnt_high != 0 && a == t.tcnt_high)) return fmt::format("TCNT{}", t.index);
        if (a == t.tccra) return fmt::format("TCCR{}A", t.index);
        if (a == t.tccrb) return fmt::format("TCCR{}B", t.index);
    }
    if (a == mcu.eecr) return "EECR";
    if (a == mcu.twcr) return "TWCR";
    if (a == mcu.adc.adcsra) return "ADCSRA";
    return fmt::format("I/O 0x{:02x}", a);
}

}  // namespace

struct FastForward::Loop {
    SkippedLoop info;
    uint16_t sp = 0;
    std::vector<uint32_t> pcs;
    std::vector<uint16_t> sps;        ///< per step: SP before it
    std::vector<uint32_t> step_ends;  ///< per step: cycles from the anchor to its end
    /// Per step: the bytes it accessed through a pointer register (LD/ST X,
    /// Y, Z), checked again on the verification pass; other steps' addresses
    /// follow from the path and SP.
    std::vector<StepAccess> accesses;
    std::vector<bool> through_pointer;
    std::vector<uint16_t> carried;
    uint8_t carried_flags = 0;  ///< SREG bits read before written, and written
    uint32_t timers_read = 0;  ///< bit n: the pass reads timers_[n]'s TCNT or flags
    LoopSpan span;
};

struct FastForward::Snapshot {
    Cycles cycle = 0;
    uint32_t pc = 0;
    uint8_t sreg[8] = {};
    int8_t interrupt_state = 0;
};

FastForward::FastForward(AvrCore& core, const std::vector<ReplayableTimer>& replayable,
                         const std::unordered_map<uint16_t, IoWatchers>& watchers)
    : core_(core),
      avr_(core.raw()),
      mcu_(core.mcu()),
      replayable_(replayable),
      watchers_(watchers),
      state_((mcu_.flash_bytes + 1) / 2, kUnknown),
      path_(state_.size(), kUnknown) {
    for (avr_io_t* io : simavr_io_modules(avr_, "timer")) timers_.push_back(io);
    saved_data_.resize(static_cast<std::size_t>(avr_->ramend) + 1);
}

FastForward::~FastForward() = default;

CpuView FastForward::cpu() const {
    CpuView v;
    v.data = avr_->data;
    v.sp = core_.stack_pointer();
    v.sreg_address = mcu_.sreg;
    v.pc_bytes = mcu_.pc_bytes;
    return v;
}

bool FastForward::after_batch(const bool& halt_a, const bool& halt_b) {
    if (avr_->state != cpu_Running || halt_a || halt_b) return false;  // the run stops here
    const uint32_t pc = avr_->pc;
    if ((pc >> 1) >= state_.size()) return false;
    const int32_t st = slot(pc);
    if (st >= 0) return try_jump(loops_[static_cast<std::size_t>(st)]);
    if (enter_learned_pass(halt_a, halt_b)) return true;
    if (st < kUnknown) {
        ++refused_[static_cast<std::size_t>(-2 - st)].visits;
        return false;
    }
    const uint16_t sp = core_.stack_pointer();
    bool seen = false;
    for (unsigned i = 0; i < kHistory; ++i) seen = seen || (last_pc_[i] == pc && last_sp_[i] == sp);
    last_pc_[last_next_] = pc;
    last_sp_[last_next_] = sp;
    last_next_ = (last_next_ + 1) % kHistory;
    // A PC on a learned pass is in a loop: learn it as an anchor of its own
    // (the same loop, or another through the same code), so that later batch
    // ends there jump at once.
    if (!(seen || path_[pc >> 1] >= 0) || avr_->cycle < no_learning_before_) return false;
    return learn(pc, halt_a, halt_b);
}

bool FastForward::enter_learned_pass(const bool& halt_a, const bool& halt_b) {
    const int32_t on = path_[avr_->pc >> 1];
    if (on < 0 || avr_->cycle < no_jump_before_) return false;
    // Inside a learned pass, not at its anchor: on to the anchor, and jump there.
    Loop& loop = loops_[static_cast<std::size_t>(on)];
    switch (walk_to_anchor(loop, halt_a, halt_b)) {
        case Walk::kArrived: (void)try_jump(loop); return true;
        case Walk::kLeft: {
            // Off this pass, perhaps onto another loop's anchor through the same code.
            const int32_t st = slot(avr_->pc);
            if (st >= 0 && avr_->state == cpu_Running && !halt_a && !halt_b) {
                (void)try_jump(loops_[static_cast<std::size_t>(st)]);
            }
            return true;
        }
        case Walk::kNotOnPath: break;
    }
    return false;
}

bool FastForward::record_pass(uint32_t anchor, std::vector<RecordedStep>& steps, Cycles& cycles,
                              const bool& halt_a, const bool& halt_b) {
    const Cycles start = avr_->cycle;
    const uint16_t sp = core_.stack_pointer();
    const auto vectors_end = static_cast<uint32_t>(mcu_.vector_count() * mcu_.vector_bytes);
    steps.clear();
    while (steps.size() < kMaxPassSteps) {
        const uint32_t pc = avr_->pc;
        if (!steps.empty() && pc == anchor && core_.stack_pointer() == sp) {
            cycles = avr_->cycle - start;
            return true;
        }
        steps.push_back({pc, core_.stack_pointer(), step_access(core_.flash_word(pc), core_.flash_word(pc + 2), cpu())});
        if (!step_one() || halt_a || halt_b) return false;
        steps.back().cycles_after = static_cast<uint32_t>(avr_->cycle - start);
        if (avr_->pc < vectors_end || avr_->cycle - start > kMaxPassCycles) return false;  // an interrupt
    }
    return false;
}

bool FastForward::learn(uint32_t anchor, const bool& halt_a, const bool& halt_b) {
    avr_->run_cycle_limit = 1;
    std::vector<RecordedStep> first;
    std::vector<RecordedStep> second;
    Cycles c1 = 0;
    Cycles c2 = 0;
    bool ok = record_pass(anchor, first, c1, halt_a, halt_b);
    const Snapshot between = snapshot();  // the state the second pass starts from
    ok = ok && record_pass(anchor, second, c2, halt_a, halt_b);
    avr_->run_cycle_limit = core_.free_run_limit();  // 1 if an interrupt entry switched a step watch on
    no_learning_before_ = avr_->cycle + kLearningBackoff;
    if (!ok) return true;
    const bool same_path = c1 == c2 && first.size() == second.size() &&
                           std::equal(first.begin(), first.end(), second.begin(),
                                      [](const RecordedStep& a, const RecordedStep& b) { return a.pc == b.pc; });
    if (!same_path) {
        auto& tries = tries_[anchor];
        if (++tries >= kMaxLearningTries) refuse(anchor, "its passes do not repeat one instruction path");
        return true;
    }
    const PassAnalysis analysis = analyse_pass(second, 0x20, mcu_.sram_start, mcu_.spl);
    Loop loop;
    std::string why = analysis.refusal;
    if (why.empty()) why = accept_io(analysis, loop.timers_read);
    for (uint16_t a : analysis.carried) {
        if (!why.empty()) break;
        if (avr_->data[a] == saved_data_[a]) continue;
        why = a < 32 ? fmt::format("changes r{} from pass to pass", a)
                     : fmt::format("changes 0x{:04x} from pass to pass", a);
    }
    if (why.empty() && !flags_equal(analysis.carried_flags, between.sreg, avr_->sreg)) {
        why = "changes an SREG flag from pass to pass";
    }
    if (!why.empty()) {
        refuse(anchor, why);
        return true;
    }
    loop.info.anchor = anchor;
    loop.info.pass_cycles = c2;
    loop.sp = core_.stack_pointer();
    loop.carried = analysis.carried;
    loop.carried_flags = analysis.carried_flags;
    loop.info.pc_low = loop.info.pc_high = anchor;
    loop.span.min_sp = loop.span.max_sp = loop.sp;
    loop.span.io_reads = analysis.io_reads;
    for (const RecordedStep& s : second) {
        if (s.access.mem_write) {
            for (unsigned i = 0; i < s.access.count; ++i) {
                const uint16_t a = s.access.address[i];
                if (a >= mcu_.sram_start) loop.span.lowest_sram_write = std::min(loop.span.lowest_sram_write, a);
            }
        }
        loop.span.min_sp = std::min(loop.span.min_sp, s.sp);
        loop.span.max_sp = std::max(loop.span.max_sp, s.sp);
        loop.pcs.push_back(s.pc);
        loop.sps.push_back(s.sp);
        loop.step_ends.push_back(s.cycles_after);
        loop.accesses.push_back(s.access);
        const auto d = avr::decode_data_access(core_.flash_word(s.pc), 0);
        loop.through_pointer.push_back(d && d->pointer != avr::Pointer::kNone);
        loop.info.pc_low = std::min(loop.info.pc_low, s.pc);
        loop.info.pc_high = std::max(loop.info.pc_high, s.pc);
    }
    slot(anchor) = static_cast<int32_t>(loops_.size());
    for (uint32_t pc : loop.pcs) {
        if (pc != anchor && path_[pc >> 1] == kUnknown) path_[pc >> 1] = static_cast<int32_t>(loops_.size());
    }
    loops_.push_back(std::move(loop));
    for (Loop& l : loops_) l.span.pcs = &l.pcs;  // re-pointed after each growth of loops_
    return true;
}

std::string FastForward::accept_io(const PassAnalysis& analysis, uint32_t& timers_read) const {
    for (uint16_t a : analysis.io_reads) {
        if (a == mcu_.spl || a == mcu_.sph) continue;
        if (read_observed(avr_, watchers_, a)) return fmt::format("reads {}, which a part watches", io_name(mcu_, a));
        bool timer = false;
        for (std::size_t n = 0; n < timers_.size(); ++n) {
            const auto* t = static_cast<const avr_timer_t*>(timers_[n]);
            if (a == t->r_tcnt || (t->r_tcnth != 0 && a == t->r_tcnth) || a == t->overflow.raised.reg) {
                timers_read |= 1U << n;
                timer = true;
            }
        }
        const auto& io = avr_->io[AVR_DATA_TO_IO(a)];
        const bool pin = std::any_of(mcu_.ports.begin(), mcu_.ports.end(),
                                     [a](const PortRegisters& p) { return p.pin == a; });
        if (!timer && !pin && io.r.c != nullptr) {
            return fmt::format("reads {}, a read with side effects in simavr", io_name(mcu_, a));
        }
    }
    for (uint16_t a : analysis.io_writes) {
        if (a == mcu_.spl || a == mcu_.sph) continue;
        const auto& io = avr_->io[AVR_DATA_TO_IO(a)];
        if (io.w.c != nullptr || io.irq != nullptr) return fmt::format("writes {}", io_name(mcu_, a));
    }
    return {};
}

void FastForward::refuse(uint32_t anchor, std::string reason) {
    slot(anchor) = -2 - static_cast<int32_t>(refused_.size());
    refused_.push_back(RefusedLoop{anchor, fmt::format("PC 0x{:04x}: {}", anchor, reason), 0});
}

FastForward::Defer FastForward::deferrable(const avr_cycle_timer_slot_t& slot, const Loop& loop) const {
    const void* param = slot.param;
    for (const ReplayableTimer& r : replayable_) {
        if (r.fn != slot.timer || r.param != param) continue;
        if (!r.may_replay(loop.span)) return Defer::kNo;
        return r.runs == ReplayableTimer::Runs::kAtOwnCycle ? Defer::kAtOwnCycle : Defer::kReplay;
    }
    for (std::size_t n = 0; n < timers_.size(); ++n) {
        if (timers_[n] != param) continue;
        if ((loop.timers_read >> n) & 1U) return Defer::kNo;
        auto* t = static_cast<avr_timer_t*>(timers_[n]);
        if (avr_regbit_get(avr_, t->overflow.enable) != 0 || avr_regbit_get(avr_, t->icr.enable) != 0) return Defer::kNo;
        for (const avr_timer_comp_t& c : t->comp) {
            if (c.r_ocr == 0) continue;
            if (avr_regbit_get(avr_, c.interrupt.enable) != 0) return Defer::kNo;
            if (c.comp_cycles != 0 && avr_regbit_get(avr_, c.com) != 0) return Defer::kNo;  // drives its OC pin
        }
        return Defer::kReplay;
    }
    return Defer::kNo;
}

Cycles FastForward::bound(const Loop& loop) const {
    for (const avr_cycle_timer_slot_t* t = avr_->cycle_timers.timer; t != nullptr; t = t->next) {
        if (deferrable(*t, loop) == Defer::kNo) return t->when;
    }
    return std::numeric_limits<Cycles>::max();
}

bool FastForward::step_one() {
    avr_->run_cycle_count = 1;
    avr_run(avr_);
    // A watchdog reset (simavr swapped its run callback) is AvrCore's to take.
    return avr_->state == cpu_Running && !core_.event_pending();
}

bool FastForward::verify_pass(const Loop& loop) {
    for (std::size_t i = 0; i < loop.pcs.size(); ++i) {
        const uint32_t pc = avr_->pc;
        if (pc != loop.pcs[i]) return false;
        if (loop.through_pointer[i]) {
            const StepAccess a = step_access(core_.flash_word(pc), core_.flash_word(pc + 2), cpu());
            const StepAccess& b = loop.accesses[i];
            if (a.count != b.count || !std::equal(a.address.begin(), a.address.begin() + a.count, b.address.begin())) {
                return false;
            }
        }
        if (!step_one()) return false;
    }
    return avr_->pc == loop.info.anchor && core_.stack_pointer() == loop.sp;
}

bool FastForward::carried_unchanged(const Loop& loop, const Snapshot& before) const {
    for (uint16_t a : loop.carried) {
        if (avr_->data[a] != saved_data_[a]) return false;
    }
    return flags_equal(loop.carried_flags, before.sreg, avr_->sreg);
}

/// A pending cycle timer taken off simavr's list for a jump.
struct FastForward::Held {
    avr_cycle_timer_t fn;
    void* param;
    Cycles when;  ///< due at; 0 once run and not to be registered again
    bool own_cycle;
};

std::vector<FastForward::Held> FastForward::hold_timers(const Loop& loop, Cycles end) {
    std::vector<Held> held;
    for (const avr_cycle_timer_slot_t* t = avr_->cycle_timers.timer; t != nullptr && t->when <= end; t = t->next) {
        held.push_back({t->timer, t->param, t->when, deferrable(*t, loop) == Defer::kAtOwnCycle});
    }
    for (const Held& h : held) avr_cycle_timer_cancel(avr_, h.fn, h.param);
    return held;
}

void FastForward::release(const Loop& loop, const std::vector<Held>& held, Cycles now) {
    // Registered again at their own cycles (a delta past now wraps to the
    // same absolute cycle), in order. Those the jump passed run now, in
    // order, each with the clock where executing the passes would have run
    // it: the end of the instruction that reached its cycle (a flag raised
    // there is stamped with it: IsrMonitor::pending_since).
    for (const Held& h : held) {
        if (h.when != 0) avr_cycle_timer_register(avr_, h.when - avr_->cycle, h.fn, h.param);
    }
    const Cycles end = avr_->cycle;
    for (const avr_cycle_timer_slot_t* t = avr_->cycle_timers.timer; t != nullptr && t->when <= end;
         t = avr_->cycle_timers.timer) {
        avr_->cycle = fires_at(loop, now, t->when);
        avr_cycle_timer_process(avr_);
    }
    avr_->cycle = end;
    avr_cycle_timer_process(avr_);  // sets simavr's next batch length
}

FastForward::Snapshot FastForward::snapshot() {
    Snapshot s;
    s.cycle = avr_->cycle;
    s.pc = avr_->pc;
    std::memcpy(s.sreg, avr_->sreg, sizeof s.sreg);
    s.interrupt_state = avr_->interrupt_state;
    std::memcpy(saved_data_.data(), avr_->data, saved_data_.size());
    return s;
}

void FastForward::restore(const Snapshot& before) {
    std::memcpy(avr_->data, saved_data_.data(), saved_data_.size());
    std::memcpy(avr_->sreg, before.sreg, sizeof before.sreg);
    avr_->pc = before.pc;
    avr_->cycle = before.cycle;
    avr_->interrupt_state = before.interrupt_state;
}

/// The cycle at which simavr runs a timer due at `when` inside passes that
/// started at `now`: the end of the instruction that reaches it.
Cycles FastForward::fires_at(const Loop& loop, Cycles now, Cycles when) {
    const Cycles pass = loop.info.pass_cycles;
    const Cycles into = (when - now) % pass;
    if (into == 0) return when;
    const auto it = std::lower_bound(loop.step_ends.begin(), loop.step_ends.end(), into);
    return when - into + (it == loop.step_ends.end() ? pass : *it);
}

// The verified passes wrote no I/O and took no interrupt, so a part's step
// due inside them reads what it would have read at its own cycle. Each runs
// there, in order, while nothing it scheduled falls inside the jump.
// Returns false if the jump must be taken back; `stop_at`: the cycle of a
// step that requested a stop (0: none), which the caller defers to there.
bool FastForward::run_own_cycle_timers(const Loop& loop, std::vector<Held>& held, Cycles now, Cycles end,
                                       Cycles& stop_at) {
    for (Held& h : held) {
        if (!h.own_cycle) continue;
        while (h.when != 0 && h.when <= end) {
            if (bound(loop) <= end) return false;  // an earlier step scheduled an event inside the jump
            const Cycles at = h.when;
            avr_->cycle = fires_at(loop, now, at);
            const Cycles next = h.fn(avr_, at, h.param);
            avr_->cycle = end;
            h.when = next > at ? next : 0;
            if (core_.stop_requested()) {
                core_.clear_stop_request();
                stop_at = at;
                return false;
            }
        }
    }
    return bound(loop) > end;
}

// Steps from a PC of the pass (with its SP) on along the pass to the anchor;
// stops where the run leaves it (a branch taken otherwise, an interrupt).
FastForward::Walk FastForward::walk_to_anchor(const Loop& loop, const bool& halt_a, const bool& halt_b) {
    const uint16_t sp = core_.stack_pointer();
    std::size_t i = 1;
    while (i < loop.pcs.size() && (loop.pcs[i] != avr_->pc || loop.sps[i] != sp)) ++i;
    if (i == loop.pcs.size()) return Walk::kNotOnPath;
    avr_->run_cycle_limit = 1;
    for (; i < loop.pcs.size(); ++i) {
        if (avr_->pc != loop.pcs[i] || !step_one() || halt_a || halt_b) break;
    }
    avr_->run_cycle_limit = core_.free_run_limit();
    const bool arrived = i == loop.pcs.size() && avr_->state == cpu_Running && !halt_a && !halt_b &&
                         avr_->pc == loop.info.anchor && core_.stack_pointer() == loop.sp;
    return arrived ? Walk::kArrived : Walk::kLeft;
}

// Jumps as far as the loop's path holds. A verification pass that leaves
// the path (delay() counting down one more millisecond) shows that the
// path changes by its end: the next attempt aims at half the distance
// to there, so the jumps close in on the change by bisection. A jump taken
// back for an event a part's step scheduled inside it is tried again up to
// that event (the steps already run stay run).
bool FastForward::try_jump(Loop& loop) {
    if (avr_->cycle < no_jump_before_ || core_.stack_pointer() != loop.sp) return false;
    // interrupt_state < 0: the I flag was just set (the instruction after SEI
    // or OUT SREG runs first); with nothing pending that is part of the pass.
    if (avr_->interrupt_state > 0 || avr_has_pending_interrupts(avr_) != 0) return false;
    constexpr Cycles kNoChangeSeen = std::numeric_limits<Cycles>::max();
    Cycles changes_by = kNoChangeSeen;  // the path is seen to change by then
    bool ran = false;
    for (int attempt = 0; attempt < kMaxJumpAttempts; ++attempt) {
        const Cycles now = avr_->cycle;
        const Cycles cap = changes_by == kNoChangeSeen ? kNoChangeSeen : now + (changes_by - now) / 2;
        const Jump outcome = jump_once(loop, now, cap, changes_by);
        if (outcome == Jump::kTooShort) break;
        ran = true;
        if (outcome == Jump::kStopDeferred) return true;
        if (outcome == Jump::kSkipped && changes_by == kNoChangeSeen) return true;
    }
    if (changes_by != kNoChangeSeen) no_jump_before_ = changes_by;
    return ran;
}

FastForward::Jump FastForward::jump_once(Loop& loop, Cycles now, Cycles cap, Cycles& changes_by) {
    const Cycles pass = loop.info.pass_cycles;
    const Cycles edge = std::min(bound(loop), cap);
    if (edge <= now + (kMinPassesPerJump + 2) * pass + kVerifyMargin) return Jump::kTooShort;
    const Cycles k = (edge - 1 - kVerifyMargin - now) / pass - 1;  // the verification pass ends before the edge
    const Cycles end = now + (k + 1) * pass;
    std::vector<Held> held = hold_timers(loop, end);
    const Snapshot before = snapshot();
    avr_->run_cycle_limit = 1;
    avr_->cycle = now + k * pass;
    const bool verified = verify_pass(loop) && avr_->cycle == end && carried_unchanged(loop, before);
    avr_->run_cycle_limit = core_.free_run_limit();
    Jump outcome = Jump::kSkipped;
    Cycles stop_at = 0;
    if (!verified) {
        restore(before);
        ++loop.info.mismatches;
        changes_by = end;
        outcome = Jump::kMismatch;
    } else if (!run_own_cycle_timers(loop, held, now, end, stop_at)) {
        restore(before);
        ++loop.info.taken_back;
        outcome = stop_at != 0 ? Jump::kStopDeferred : Jump::kTakenBack;
    } else {
        ++loop.info.skips;
        loop.info.cycles_skipped += k * pass;
        cycles_skipped_ += k * pass;
    }
    release(loop, held, now);
    if (stop_at != 0) core_.stop_after(stop_at - now);
    return outcome;
}

FastForwardStats FastForward::stats() const {
    FastForwardStats s;
    s.cycles_skipped = cycles_skipped_;
    for (const Loop& l : loops_) {
        s.skips += l.info.skips;
        s.mismatches += l.info.mismatches;
        s.taken_back += l.info.taken_back;
        s.loops.push_back(l.info);
        s.loops.back().path = l.pcs;
    }
    for (const RefusedLoop& r : refused_) {
        if (r.visits > 0) s.refused.push_back(r);
    }
    std::stable_sort(s.refused.begin(), s.refused.end(),
                     [](const RefusedLoop& a, const RefusedLoop& b) { return a.visits > b.visits; });
    return s;
}

}  // namespace ddmr::hil
