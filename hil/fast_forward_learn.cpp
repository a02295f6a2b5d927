#include "hil/fast_forward.hpp"

#include <avr_timer.h>
#include <sim_avr.h>

#include <fmt/format.h>

#include <algorithm>
#include <memory>
#include <string>

#include "hil/avr_core.hpp"
#include "hil/avr_decode.hpp"
#include "hil/fast_forward_loop.hpp"
#include "hil/io_register_name.hpp"
#include "hil/mcu.hpp"

// Learning: a candidate anchor's two passes are stepped and recorded, and
// the loop is kept, with its pass, or refused, with the reason
// (hil/fast_forward.hpp).

namespace ddmr::hil {
namespace {

/// A pass longer than this is not a loop worth skipping.
constexpr std::size_t kMaxPassSteps = 600;
constexpr Cycles kMaxPassCycles = 2000;
/// What is recorded to find the period of a PC passed several times per
/// period: two periods of the longest pass.
constexpr std::size_t kMaxPeriodSteps = 2 * kMaxPassSteps;
constexpr Cycles kMaxPeriodCycles = 2 * kMaxPassCycles;
/// After a learning attempt an interrupt or a stop cut short.
constexpr Cycles kLearningBackoff = 4096;
/// Passes that twice left their path before it repeated: refused after this
/// many tries. 8 rather than 16: case 1 steps 863 such tries instead of
/// 1,859 (its control loop's arithmetic has many PCs that come back), 2 %
/// fewer host instructions (callgrind), the same share of cycles skipped.
constexpr int kMaxLearningTries = 8;
/// A try whose pass ran past kMaxPassCycles counts as this many (it stepped
/// that long): one such try refuses the anchor (case 1: 1.5 % fewer host
/// instructions than with 4, callgrind; the share skipped the same).
constexpr int kLongTryWeight = 8;

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

}  // namespace

using ff_detail::flags_equal;

int32_t FastForward::loop_for(uint32_t pc, uint16_t sp) const {
    int32_t i = state_[pc >> 1];
    while (i >= 0 && loops_[static_cast<std::size_t>(i)].sp != sp) i = loops_[static_cast<std::size_t>(i)].next_at_pc;
    return i >= 0 ? i : kUnknown;
}

void FastForward::link(Loop&& loop) {
    const auto index = static_cast<int32_t>(loops_.size());
    int32_t* next = &slot(loop.info.anchor);
    while (*next >= 0) next = &loops_[static_cast<std::size_t>(*next)].next_at_pc;
    *next = index;
    if (loop.refusal == kUnknown) {
        for (uint32_t pc : loop.pcs) {
            if (pc != loop.info.anchor && path_[pc >> 1] == kUnknown) path_[pc >> 1] = index;
        }
        std::unordered_map<uint64_t, int> visits;
        for (std::size_t i = 0; i < loop.pcs.size(); ++i) ++visits[pass_key(loop.pcs[i], loop.sps[i])];
        for (std::size_t i = 1; i < loop.pcs.size(); ++i) {
            const uint64_t key = pass_key(loop.pcs[i], loop.sps[i]);
            if (visits[key] > 1) {
                ambiguous_.insert(key);
            } else {
                on_pass_.emplace(key, index);
            }
        }
    }
    loops_.push_back(std::move(loop));
    for (Loop& l : loops_) l.span.pcs = &l.pcs;  // re-pointed after each growth of loops_
}

// Steps one pass from the anchor back to it. With `follow` (the first
// pass), stops as soon as this one leaves its path.
FastForward::Record FastForward::record_pass(uint32_t anchor, std::vector<RecordedStep>& steps, Cycles& cycles,
                                             const std::vector<RecordedStep>* follow, const bool& halt_a,
                                             const bool& halt_b, IoBitUse* bits) {
    const Cycles start = avr_->cycle;
    const uint16_t sp = core_.stack_pointer();
    const uint32_t vectors_end = ff_detail::vector_table_end(mcu_);
    steps.clear();
    while (steps.size() < kMaxPassSteps) {
        const uint32_t pc = avr_->pc;
        if (!steps.empty() && pc == anchor && core_.stack_pointer() == sp) {
            cycles = avr_->cycle - start;
            return follow != nullptr && steps.size() != follow->size() ? Record::kDiffers : Record::kPass;
        }
        if (follow != nullptr && (steps.size() >= follow->size() || (*follow)[steps.size()].pc != pc)) {
            return Record::kDiffers;
        }
        const uint16_t w0 = core_.flash_word(pc);
        steps.push_back({pc, core_.stack_pointer(), step_access(w0, core_.flash_word(pc + 2), cpu())});
        if (bits != nullptr) bits->step(w0, steps.back().access, cpu());
        if (follow != nullptr && writes_checked_io(steps.back().access) && !write_inert(pc)) {
            not_inert_ = steps.back().access.address[0];
            return Record::kWrites;
        }
        if (!step_one() || halt_a || halt_b) return Record::kCut;
        steps.back().cycles_after = static_cast<uint32_t>(avr_->cycle - start);
        if (avr_->pc < vectors_end) return Record::kCut;  // an interrupt
        if (avr_->cycle - start > kMaxPassCycles) return Record::kTooLong;
    }
    return Record::kTooLong;
}

bool FastForward::learn(uint32_t anchor, const bool& halt_a, const bool& halt_b, bool seek_period) {
    avr_->run_cycle_limit = 1;
    const uint16_t anchor_sp = core_.stack_pointer();
    std::vector<RecordedStep> first;
    std::vector<RecordedStep> second;
    Cycles c1 = 0;
    Cycles c2 = 0;
    Record r = record_pass(anchor, first, c1, nullptr, halt_a, halt_b);
    const Snapshot between = snapshot();  // the state the second pass starts from
    IoBitUse bits(followed_registers_, 0x20, mcu_.sram_start, mcu_.spl);
    if (r == Record::kPass) r = record_pass(anchor, second, c2, &first, halt_a, halt_b, &bits);
    avr_->run_cycle_limit = core_.free_run_limit();  // 1 if an interrupt entry switched a step watch on
    no_learning_before_ = avr_->cycle + kLearningBackoff;
    if (r == Record::kCut) return true;  // an interrupt or a stop: try again later
    int& tries = tries_[uint64_t{anchor} << 16 | anchor_sp];
    bool long_try = r == Record::kTooLong;
    if (r == Record::kDiffers && seek_period && tries == 0) {  // the period is looked for once per anchor
        if (learn_period(halt_a, halt_b)) return true;
        long_try = true;  // it stepped up to two long passes
    }
    if (r != Record::kPass || c1 != c2) {
        // A pass that went on too long is a longer loop's (or none): each
        // try steps up to kMaxPassCycles, so it is refused as soon as passes
        // that do not repeat are.
        tries += long_try ? kLongTryWeight : 1;
        if (tries >= kMaxLearningTries) {
            refuse(anchor, anchor_sp, learning_refusal(r));
        }
        return true;
    }
    const PassAnalysis analysis = analyse_pass(second, 0x20, mcu_.sram_start, mcu_.spl);
    Loop loop;
    std::string why = analysis.refusal;
    if (why.empty()) why = accept_io(analysis);
    if (why.empty()) why = accept_writes(analysis);
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
        refuse(anchor, anchor_sp, why);
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
    loop.span.io_writes = analysis.io_writes;
    loop.span.io_bits = bits.finish();
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
        loop.checked_write.push_back(writes_checked_io(s.access));
        loop.info.pc_low = std::min(loop.info.pc_low, s.pc);
        loop.info.pc_high = std::max(loop.info.pc_high, s.pc);
    }
    // Anchors on one cycle of PCs see its changes of path alike.
    for (const Loop& l : loops_) {
        if (l.info.pass_cycles == loop.info.pass_cycles && l.info.pc_low == loop.info.pc_low &&
            l.info.pc_high == loop.info.pc_high && l.pcs.size() == loop.pcs.size()) {
            loop.changes = l.changes;
        }
    }
    if (!loop.changes) loop.changes = std::make_shared<ChangeTrack>();
    link(std::move(loop));
    return true;
}

// From wherever the run is (inside the period of a PC whose passes
// differ): records up to two periods of the longest pass, finds the
// shortest shift at which the PCs, SPs and instruction cycles repeat over
// the rest of the record, then steps on to the first PC (with its SP) that
// one period runs through once, and learns that PC as the loop's anchor.
bool FastForward::learn_period(const bool& halt_a, const bool& halt_b) {
    const uint32_t vectors_end = ff_detail::vector_table_end(mcu_);
    std::vector<uint64_t> keys;
    std::vector<Cycles> lengths;
    keys.reserve(kMaxPeriodSteps);
    lengths.reserve(kMaxPeriodSteps);
    const Cycles start = avr_->cycle;
    // One instruction per step, even one whose write registers a cycle
    // timer (simavr then sets the batch length from the limit).
    avr_->run_cycle_limit = 1;
    const auto stepped = [this, vectors_end, &halt_a, &halt_b] {
        const bool on = step_one() && !halt_a && !halt_b && avr_->pc >= vectors_end;
        if (!on) avr_->run_cycle_limit = core_.free_run_limit();
        return on;
    };
    while (keys.size() < kMaxPeriodSteps && avr_->cycle - start < kMaxPeriodCycles) {
        keys.push_back(pass_key(avr_->pc, core_.stack_pointer()));
        const Cycles before = avr_->cycle;
        if (!stepped()) return false;
        lengths.push_back(avr_->cycle - before);
    }
    avr_->run_cycle_limit = core_.free_run_limit();
    const std::size_t n = keys.size();
    std::size_t period = 0;
    for (std::size_t p = 2; p <= n / 2 && period == 0; ++p) {
        if (keys[p] != keys[0]) continue;
        bool repeats = true;
        for (std::size_t i = 0; i + p < n && repeats; ++i) repeats = keys[i] == keys[i + p] && lengths[i] == lengths[i + p];
        if (repeats) period = p;
    }
    if (period == 0) return false;
    std::size_t once = period;
    for (std::size_t i = 0; i < period && once == period; ++i) {
        if (std::count(keys.begin(), keys.begin() + static_cast<std::ptrdiff_t>(period), keys[i]) == 1) once = i;
    }
    if (once == period) return false;
    avr_->run_cycle_limit = 1;
    for (std::size_t i = 0; i < period && pass_key(avr_->pc, core_.stack_pointer()) != keys[once]; ++i) {
        if (!stepped()) return false;
    }
    avr_->run_cycle_limit = core_.free_run_limit();
    if (pass_key(avr_->pc, core_.stack_pointer()) != keys[once] || loop_for(avr_->pc, core_.stack_pointer()) != kUnknown) {
        return false;
    }
    return learn(avr_->pc, halt_a, halt_b, /*seek_period=*/false);
}

std::string FastForward::accept_io(const PassAnalysis& analysis) const {
    for (uint16_t a : analysis.io_reads) {
        if (a == mcu_.spl || a == mcu_.sph) continue;
        if (read_observed(avr_, watchers_, a)) return fmt::format("reads {}, which a part watches", io_register_name(mcu_, a));
        // TCNTn: simavr's read computes the count from the clock, changing nothing.
        const bool count = std::any_of(timers_.begin(), timers_.end(), [a](const void* m) {
            const auto* t = static_cast<const avr_timer_t*>(m);
            return a == t->r_tcnt || (t->r_tcnth != 0 && a == t->r_tcnth);
        });
        const bool followed = std::find(followed_registers_.begin(), followed_registers_.end(), a) != followed_registers_.end();
        const auto& io = avr_->io[AVR_DATA_TO_IO(a)];
        if (!count && !followed && io.r.c != nullptr) {
            return fmt::format("reads {}, a read with side effects in simavr", io_register_name(mcu_, a));
        }
    }
    return {};
}

bool FastForward::io_observed(uint16_t address) const { return read_observed(avr_, watchers_, address); }

std::string FastForward::learning_refusal(Record r) const {
    switch (r) {
        case Record::kTooLong:
            return fmt::format("its pass is longer than {} cycles or {} instructions", kMaxPassCycles, kMaxPassSteps);
        case Record::kWrites:
            return fmt::format("writes {} a new value, or where simavr's handling of the write is seen "
                               "(a pin it raises again that reads otherwise, a PCINT mask bit, a timer it re-arms)",
                               io_register_name(mcu_, not_inert_));
        default: return "its passes do not repeat one instruction path";
    }
}

// A PC that anchors loops at other stack depths keeps them: the refusal
// holds at this SP only.
void FastForward::refuse(uint32_t anchor, uint16_t sp, std::string reason) {
    const auto index = static_cast<int32_t>(refused_.size());
    refused_.push_back(RefusedLoop{anchor, fmt::format("PC 0x{:04x}: {}", anchor, reason), 0});
    if (slot(anchor) < 0) {
        slot(anchor) = -2 - index;
        return;
    }
    Loop refusal;
    refusal.info.anchor = anchor;
    refusal.sp = sp;
    refusal.refusal = index;
    link(std::move(refusal));
}

}  // namespace ddmr::hil
