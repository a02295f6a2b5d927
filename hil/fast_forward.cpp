#include "hil/fast_forward.hpp"

#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_regbit.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <string>
#include <utility>

#include "hil/avr_core.hpp"
#include "hil/fast_forward_loop.hpp"
#include "hil/mcu.hpp"
#include "hil/simavr_io.hpp"

// Jumps: bounds, the held cycle timers, the verification pass, bisection
// and prediction of a loop's changes of path (hil/fast_forward.hpp).

namespace ddmr::hil {
namespace {

/// Fewer passes than this per jump do not pay for the verification pass.
constexpr Cycles kMinPassesPerJump = 1;
/// How far a located change of path, or a period measured between two, may
/// be off [passes]: the bisection locates a change to within 3 passes after it.
constexpr Cycles kPredictionSlackPasses = 4;
/// The window around a predicted change that runs without jumps [passes].
constexpr Cycles kWindowBeforePasses = 3;
constexpr Cycles kWindowAfterPasses = 2;
/// Periods a period must have been measured over to be predicted at once in
/// a new phase (a new call of delay()).
constexpr Cycles kSteadyPeriods = 4;
/// A period shorter than this many slacks is not predicted.
constexpr Cycles kMinPeriodSlacks = 8;
/// Checked passes in a row that keep the path but change a loop-carried byte: the loop is refused.
constexpr unsigned kMaxFutileTries = 8;
/// Changes predicted in a row before one is located again.
constexpr unsigned kMaxBlindChanges = 16;
/// Cycles kept between a verification pass's end and the bound: an
/// instruction that leaves the path may take more cycles than on the
/// learned pass (a skip, a taken branch: at most a 5-cycle RET/CALL more),
/// and must still end before the bound's timer, which could raise an
/// interrupt the restore cannot take back.
constexpr Cycles kVerifyMargin = 5;
/// Learned passes walked along in a row from one batch end (enter_learned_pass).
constexpr int kMaxHops = 3;
/// Jumps tried in a row at one anchor (bisection toward a change of path,
/// retries up to an event a part's step scheduled).
constexpr int kMaxJumpAttempts = 12;
/// Instructions stepped at most from a batch end on a PC a learned pass
/// runs through more than once (after_batch).
constexpr int kMaxUndecidedSteps = 16;

/// The room a jump over passes of `pass` cycles needs before its bound:
/// kMinPassesPerJump passes skipped, the verification pass, the pass that
/// rounding down to whole passes may lose (jump_once), and the margin.
constexpr Cycles shortest_jump(Cycles pass) { return (kMinPassesPerJump + 2) * pass + kVerifyMargin; }

/// True if a timer counts the edges on its Tn pin (CSn2:0 = 6 or 7; simavr
/// 1.6 hooks avr_timer_irq_ext_clock on the pin's IRQ): an edge a part puts
/// there, or an OC output changing it, moves the count at the edge's own
/// time, which a replay after a jump would not. Then nothing is replayed.
bool a_timer_counts_pin_edges(const std::vector<void*>& timers) {
    return std::any_of(timers.begin(), timers.end(), [](const void* m) {
        return (static_cast<const avr_timer_t*>(m)->ext_clock_flags & AVR_TIMER_EXTCLK_FLAG_TN) != 0;
    });
}

}  // namespace

using ff_detail::flags_equal;

FastForward::FastForward(AvrCore& core, const std::vector<ReplayableTimer>& replayable,
                         const std::unordered_map<uint16_t, IoWatchers>& watchers)
    : core_(core),
      avr_(core.raw()),
      mcu_(core.mcu()),
      replayable_(replayable),
      watchers_(watchers),
      state_((mcu_.flash_bytes + 1) / 2, kUnknown),
      path_(state_.size(), kUnknown) {
    for (avr_io_t* io : simavr_io_modules(avr_, "timer")) {
        timers_.push_back(io);
        timer_reach_.emplace_back(avr_, mcu_, core.board(), io);
    }
    for (avr_io_t* io : simavr_io_modules(avr_, "port")) ports_.push_back(io);
    for (const PortRegisters& p : mcu_.ports) followed_registers_.push_back(p.pin);
    for (void* io : timers_) {
        const avr_regbit_t& flags = static_cast<const avr_timer_t*>(io)->overflow.raised;
        const auto known = std::find(followed_registers_.begin(), followed_registers_.end(), flags.reg);
        if (flags.reg != 0 && known == followed_registers_.end()) followed_registers_.push_back(flags.reg);
    }
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

// A batch end on a learned pass, at a PC the pass runs through more than
// once and where nothing else is anchored (which visit?), steps on to a PC
// that tells: batches of a period that is a multiple of the pass (256
// cycles, four passes of delay(), between the looks of a profiled run)
// would otherwise end there every time.
bool FastForward::after_batch(const bool& halt_a, const bool& halt_b) {
    bool ran = false;
    for (int i = 0; i < kMaxUndecidedSteps; ++i) {
        if (avr_->state != cpu_Running || halt_a || halt_b) return ran;  // the run stops here
        const uint64_t key = pass_key(avr_->pc, core_.stack_pointer());
        const bool undecided = ambiguous_.count(key) != 0 && on_pass_.count(key) == 0 &&
                               loop_for(avr_->pc, core_.stack_pointer()) == kUnknown;
        if (!undecided) return look(halt_a, halt_b) || ran;
        avr_->run_cycle_limit = 1;
        const bool on = step_one();
        avr_->run_cycle_limit = core_.free_run_limit();
        ran = true;
        // An interrupt entered: the core's to follow (a step watch it switches on).
        if (!on || avr_->pc < ff_detail::vector_table_end(mcu_)) return true;
    }
    return ran;
}

bool FastForward::look(const bool& halt_a, const bool& halt_b) {
    const uint32_t pc = avr_->pc;
    if ((pc >> 1) >= state_.size()) return false;
    const uint16_t sp = core_.stack_pointer();
    const int32_t st = slot(pc);
    const int32_t here = loop_for(pc, sp);
    if (here >= 0) {
        Loop& loop = loops_[static_cast<std::size_t>(here)];
        if (loop.refusal == kUnknown) return try_jump(loop);
        // Refused here, but on another loop's pass?
        if (const Entered e = enter_learned_pass(halt_a, halt_b); e != Entered::kNo) return e == Entered::kRan;
        ++refused_[static_cast<std::size_t>(loop.refusal)].visits;
        return false;
    }
    if (const Entered e = enter_learned_pass(halt_a, halt_b); e != Entered::kNo) return e == Entered::kRan;
    if (ambiguous_.count(pass_key(pc, sp)) != 0) return false;  // on a learned pass, at which visit?
    if (st < kUnknown) {
        ++refused_[static_cast<std::size_t>(-2 - st)].visits;
        return false;
    }
    bool seen = false;
    for (unsigned i = 0; i < kHistory; ++i) seen = seen || (last_pc_[i] == pc && last_sp_[i] == sp);
    last_pc_[last_next_] = pc;
    last_sp_[last_next_] = sp;
    last_next_ = (last_next_ + 1) % kHistory;
    // A PC on a learned pass is in a loop: learn it as an anchor of its own
    // (the same loop, or another through the same code), so that later batch
    // ends there jump at once. So is an anchor met at another stack depth.
    if (!(seen || st >= 0 || path_[pc >> 1] >= 0) || avr_->cycle < no_learning_before_) return false;
    return learn(pc, halt_a, halt_b);
}

FastForward::Entered FastForward::enter_learned_pass(const bool& halt_a, const bool& halt_b) {
    if (avr_->cycle < no_jump_before_) return Entered::kNo;
    // Inside a learned pass, not at its anchor (with the SP the pass has
    // there): on to the first anchor on the way (its own, or another
    // loop's through the same code), and jump there. Off it, the run may be on
    // another loop's pass or anchor through the same code (a line sensor
    // changed the path): on to that one, a few times at most.
    bool ran = false;
    for (int hop = 0; hop < kMaxHops; ++hop) {
        const auto on = on_pass_.find(pass_key(avr_->pc, core_.stack_pointer()));
        if (on == on_pass_.end()) break;
        Loop& loop = loops_[static_cast<std::size_t>(on->second)];
        if (!ran && !jump_may_follow(loop)) return Entered::kWaiting;
        const Walk walk = walk_to_anchor(loop, halt_a, halt_b, /*any_anchor=*/true);
        if (walk == Walk::kNotOnPath) break;
        ran = true;
        if (walk == Walk::kArrived || walk == Walk::kAtAnchor) break;
        // A watchdog reset (simavr swapped its run callback) or a stop is the core's to take.
        if (avr_->state != cpu_Running || halt_a || halt_b || core_.event_pending() || core_.stop_requested()) {
            return Entered::kRan;
        }
    }
    if (!ran) return Entered::kNo;
    if (Loop* here = loop_here()) (void)try_jump(*here);
    return Entered::kRan;
}

FastForward::Loop* FastForward::loop_here() {
    if ((avr_->pc >> 1) >= state_.size()) return nullptr;
    const int32_t at = loop_for(avr_->pc, core_.stack_pointer());
    if (at < 0) return nullptr;
    Loop& loop = loops_[static_cast<std::size_t>(at)];
    return loop.refusal == kUnknown ? &loop : nullptr;
}

// The anchor is at most one pass away; a jump from there needs room for
// kMinPassesPerJump passes, the verification pass and the margin before
// the next event. Without it, stepping to the anchor instruction by
// instruction (a long pass) gains nothing: the run goes on in batches. (A
// short pass runs to its anchor in batches, and try_jump there keeps the
// prediction of its changes of path up to date: walked always.)
bool FastForward::jump_may_follow(const Loop& loop) const {
    if (!walks_by_step(loop)) return true;
    const Cycles pass = loop.info.pass_cycles;
    return bound(loop) > avr_->cycle + pass + shortest_jump(pass);
}

FastForward::Defer FastForward::deferrable(CycleTimerFn fn, const void* param, Cycles when, const Loop& loop) const {
    if (a_timer_counts_pin_edges(timers_)) return Defer::kNo;
    for (const ReplayableTimer& r : replayable_) {
        if (r.fn != fn || r.param != param) continue;
        if (!r.may_replay(loop.span)) return Defer::kNo;
        // Instruction hooks are shown the skipped passes after the steps
        // (what they report, a VCD's loop iterations, is closed only up to
        // unsettled_from() meanwhile).
        return r.runs == ReplayableTimer::Runs::kAfterJump ? Defer::kReplay : Defer::kAtOwnCycle;
    }
    for (std::size_t n = 0; n < timers_.size(); ++n) {
        if (timers_[n] != param) continue;
        return timer_reach_[n].replayable(when, loop.span) ? Defer::kReplay : Defer::kNo;
    }
    return Defer::kNo;
}

Cycles FastForward::bound(const Loop& loop) const {
    for (const avr_cycle_timer_slot_t* t = avr_->cycle_timers.timer; t != nullptr; t = t->next) {
        if (deferrable(t->timer, t->param, t->when, loop) == Defer::kNo) return t->when;
    }
    return std::numeric_limits<Cycles>::max();
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
        held.push_back({t->timer, t->param, t->when, deferrable(t->timer, t->param, t->when, loop) == Defer::kAtOwnCycle});
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
    // A timer its owner registered again meanwhile (a part's step queued an
    // edge earlier than the held one) keeps that registration, which in
    // simavr replaces the earlier one.
    for (const Held& h : held) {
        if (h.when != 0 && !registered(h.fn, h.param)) avr_cycle_timer_register(avr_, h.when - avr_->cycle, h.fn, h.param);
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
    unsettled_from_ = now;  // the held timers run after these steps
    for (Held& h : held) {
        if (!h.own_cycle) continue;
        while (h.when != 0 && h.when <= end) {
            if (!still_deferred(loop, held, end)) return false;  // an earlier step scheduled an event inside the jump
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
    return still_deferred(loop, held, end);
}

// True if nothing a part's step scheduled bounds the jump: no timer due
// inside it that may not be deferred, registered or held (a step may queue
// an edge to a held timer's owner without registering it again).
bool FastForward::still_deferred(const Loop& loop, const std::vector<Held>& held, Cycles end) const {
    if (bound(loop) <= end) return false;
    return std::none_of(held.begin(), held.end(), [&](const Held& h) {
        return !h.own_cycle && h.when != 0 && deferrable(h.fn, h.param, h.when, loop) == Defer::kNo;
    });
}

bool FastForward::registered(CycleTimerFn fn, const void* param) const {
    for (const avr_cycle_timer_slot_t* t = avr_->cycle_timers.timer; t != nullptr; t = t->next) {
        if (t->timer == fn && t->param == param) return true;
    }
    return false;
}

// Jumps as far as the loop's path holds. A verification pass that leaves
// the path (delay() counting down one more millisecond) shows that the
// path changes by its end: the next attempt aims at half the distance
// to there, so the jumps close in on the change by bisection. A jump taken
// back for an event a part's step scheduled inside it is tried again up to
// that event (the steps already run stay run).
// A loop whose path changes at a steady period is jumped to just before
// its next change, and the passes around it run: that saves the bisection's
// tries (each a stepped pass), about eight per millisecond of delay(). A
// prediction only aims the jumps; each is verified as any other.
bool FastForward::try_jump(Loop& loop) {
    if (avr_->cycle < no_jump_before_ || core_.stack_pointer() != loop.sp) return false;
    // interrupt_state < 0: the I flag was just set (the instruction after SEI
    // or OUT SREG runs first); with nothing pending that is part of the pass.
    if (avr_->interrupt_state > 0 || avr_has_pending_interrupts(avr_) != 0) return false;
    const Cycles aim = aim_before_change(loop);
    if (aim == 0) return false;  // the change is due: it runs
    Cycles changes_by = kNoChangeSeen;  // the path is seen to change by then
    bool ran = false;
    bool differs_now = false;
    for (int attempt = 0; attempt < kMaxJumpAttempts; ++attempt) {
        const Cycles now = avr_->cycle;
        const Cycles cap = changes_by == kNoChangeSeen ? aim : now + (changes_by - now) / 2;
        const Jump outcome = jump_once(loop, now, cap, changes_by);
        if (outcome == Jump::kTooShort) break;
        ran = true;
        if (outcome == Jump::kStopDeferred) return true;
        if (outcome == Jump::kSkipped && changes_by == kNoChangeSeen) return true;
        // The first check left the path. If the path from here is already
        // another (an input differs since the loop was learned: a line
        // sensor's pin), no jump from here holds: one pass runs for real
        // to see (its cycles are not lost), before any bisection.
        if (outcome == Jump::kMismatch && attempt == 0 && loop.info.pass_cycles >= kSamplePeriod && !pass_runs_on_path(loop)) {
            differs_now = true;
            break;
        }
    }
    // Located: the change is within the shortest jump (the bisection stopped
    // on its own cap). If an event or the attempts cut it short, the passes
    // run on to the event, which may move the change, and the next try starts afresh.
    const Cycles shortest = shortest_jump(loop.info.pass_cycles);
    if (!differs_now && changes_by != kNoChangeSeen && changes_by - avr_->cycle <= 2 * shortest) {
        no_jump_before_ = changes_by;
        note_change(loop, changes_by);
    }
    if (loop.futile >= kMaxFutileTries) {
        // Checked passes kept the path but not a loop-carried byte, time
        // after time: the byte matched twice by chance when the loop was
        // learned (an SREG copy whose N and Z flags follow a time). Refused
        // at this anchor and SP; the same passes stay reachable from the
        // loop's other anchors.
        const auto index = static_cast<int32_t>(&loop - loops_.data());
        loop.refusal = static_cast<int32_t>(refused_.size());
        std::string why = fmt::format(
            "PC 0x{:04x}: a loop-carried byte changed, or an I/O write was not inert, at {} checked passes in a row",
            loop.info.anchor, kMaxFutileTries);
        refused_.push_back(RefusedLoop{loop.info.anchor, std::move(why), 0});
        for (std::size_t i = 1; i < loop.pcs.size(); ++i) {
            const auto it = on_pass_.find(pass_key(loop.pcs[i], loop.sps[i]));
            if (it != on_pass_.end() && it->second == index) on_pass_.erase(it);
        }
    }
    return ran;
}

// Steps one pass from the anchor for real (the instruction hooks see it);
// true if it followed the loop's path back to the anchor. Stops where the
// run leaves the path, enters an interrupt, or a step asks for a stop. Not
// run (true: bisect as before) if the pass could reach the next bound (the
// run's target among them: stepping must not pass it).
bool FastForward::pass_runs_on_path(const Loop& loop) {
    if (avr_->cycle + loop.info.pass_cycles + kVerifyMargin >= bound(loop)) return true;
    const bool stays_before_target = false;  // the bound above keeps the run's target out of the pass
    return walk_to_anchor(loop, stays_before_target, stays_before_target) == Walk::kArrived;
}

// Where a jump should stop short of the loop's next predicted change of
// path (kNoChangeSeen: no prediction), or 0 if the change is due now: then
// no jump is tried until just after it (the window), and no walk either.
// A located change is up to 3 passes late (the bisection stops there), so
// the change comes up to that much before the prediction: the window opens
// kWindowBefore passes before it and closes kWindowAfter passes after.
Cycles FastForward::aim_before_change(Loop& loop) {
    ChangeTrack& t = *loop.changes;
    if (!t.held) return kNoChangeSeen;
    const Cycles pass = loop.info.pass_cycles;
    const Cycles now = avr_->cycle;
    const Cycles after = kWindowAfterPasses * pass;
    if (t.at + t.period + after <= now) {  // changes that ran in a window, unseen: assumed on time
        const Cycles k = (now - t.at - after) / t.period;
        t.at += k * t.period;
        t.blind += static_cast<unsigned>(std::min<Cycles>(k, kMaxBlindChanges));
    }
    // After a few assumed changes the next is located again (bisection),
    // which checks the period and its phase.
    t.held = t.blind < kMaxBlindChanges;
    if (!t.held) return kNoChangeSeen;
    const Cycles predicted = t.at + t.period;
    const Cycles opens = predicted - kWindowBeforePasses * pass;
    // Too close to the window for a jump (one pass skipped, one verified): wait there.
    if (now + shortest_jump(pass) >= opens) {
        no_jump_before_ = predicted + after;
        return 0;
    }
    return opens;
}

// A change located by bisection (up to 3 passes before `at`). While the
// changes located keep to whole periods from the last one (to within the
// slack per period: the changes between may have run unseen, in a window),
// the period is held, and measured again over all the periods since the
// first change of the phase. Otherwise the phase broke (a new call of
// delay()): the period is kept, and predicted from this change on if it
// was measured over kSteadyPeriods or more; the interval becomes a
// candidate, held as the period if the next one matches it (the first
// period is found so). Only where jumps end is
// predicted, never the path: a wrong prediction costs time, never exactness.
void FastForward::note_change(Loop& loop, Cycles at) {
    ChangeTrack& t = *loop.changes;
    const Cycles slack = kPredictionSlackPasses * loop.info.pass_cycles;
    const Cycles interval = t.located == 0 || at <= t.located ? 0 : at - t.located;
    const auto near = [](Cycles a, Cycles b, Cycles tolerance) { return a + tolerance >= b && a <= b + tolerance; };
    const Cycles n = t.period == 0 ? 0 : (interval + t.period / 2) / t.period;
    t.held = false;
    if (interval < kMinPeriodSlacks * slack) {
        t.ref_at = at;
        t.candidate = 0;
    } else if (n >= 1 && near(interval, n * t.period, n * slack)) {
        const Cycles since = at - t.ref_at;
        const Cycles periods = (since + t.period / 2) / t.period;
        if (periods > t.periods) {
            t.period = (since + periods / 2) / periods;
            t.periods = periods;
        }
        t.held = true;
    } else if (t.candidate != 0 && near(interval, t.candidate, slack)) {
        t.period = interval;
        t.periods = 1;
        t.held = true;
    } else {
        // A new phase (delay() called again) of a period measured over
        // several: predicted from this change on (a wrong guess costs a
        // bisection; a period held by chance is not).
        t.candidate = interval;
        t.ref_at = at;
        t.held = t.periods >= kSteadyPeriods;
    }
    t.located = at;
    t.at = at;
    t.blind = 0;
}

FastForward::Jump FastForward::jump_once(Loop& loop, Cycles now, Cycles cap, Cycles& changes_by) {
    const Cycles pass = loop.info.pass_cycles;
    const Cycles edge = std::min(bound(loop), cap);
    if (edge <= now + shortest_jump(pass)) return Jump::kTooShort;
    const Cycles k = (edge - 1 - kVerifyMargin - now) / pass - 1;  // the verification pass ends before the edge
    const Cycles end = now + (k + 1) * pass;
    std::vector<Held> held = hold_timers(loop, end);
    const Snapshot before = snapshot();
    avr_->run_cycle_limit = 1;
    avr_->cycle = now + k * pass;
    const Verify checked = verify_pass(loop);
    const bool path_held = checked == Verify::kHeld && avr_->cycle == end;
    const bool verified = path_held && carried_unchanged(loop, before);
    loop.futile = (path_held && !verified) || checked == Verify::kNotInert ? loop.futile + 1 : 0;
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
        replay_to_hooks(loop, now, k + 1);
    }
    release(loop, held, now);
    unsettled_from_ = kAllSettled;
    if (stop_at != 0) core_.stop_after(stop_at - now);
    return outcome;
}

FastForwardStats FastForward::stats() const {
    FastForwardStats s;
    s.cycles_skipped = cycles_skipped_;
    for (const Loop& l : loops_) {
        if (l.refusal != kUnknown && l.info.skips == 0) continue;
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
