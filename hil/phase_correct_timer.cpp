#include "hil/phase_correct_timer.hpp"

#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_io.h>
#include <sim_regbit.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "hil/fast_forward.hpp"
#include "hil/simavr_io.hpp"
#include "hil/timer_registers.hpp"

namespace ddmr::hil {
namespace {

avr_timer_t* simavr_timer(avr_t* avr, int index) {
    for (avr_io_t* io : simavr_io_modules(avr, "timer")) {
        auto* t = reinterpret_cast<avr_timer_t*>(io);
        if (t->name == static_cast<char>('0' + index)) return t;
    }
    throw std::runtime_error("PhaseCorrectTimer: simavr has no Timer" + std::to_string(index));
}

}  // namespace

PhaseCorrectTimer::PhaseCorrectTimer(AvrCore& core, const TimerDesc& desc)
    : core_(core), desc_(desc), sim_(simavr_timer(core.raw(), desc.index)), decoder_(desc) {
    // Low bytes only: the chip moves a 16-bit value in with its low byte.
    // ASSR (Timer2): AS2 clocks the timer from the TOSC pins, not the prescaler.
    const uint16_t watched[] = {desc.tccra,    desc.tccrb,   desc.ocra_low,  desc.ocrb_low,
                                desc.ocrc_low, desc.icr_low, static_cast<uint16_t>(sim_->as2.reg)};
    std::size_t n = 0;
    for (uint16_t a : watched) {
        if (a == 0 || n == std::size(watched_)) continue;
        watched_[n++] = a;
        core_.watch_io(a, &PhaseCorrectTimer::on_register, this, AvrCore::IoReads::kIgnored);
    }
    avr_t* avr = core_.raw();
    auto& io = avr->io[AVR_DATA_TO_IO(desc.tcnt_low)];
    simavr_read_ = io.r.c;
    simavr_read_param_ = io.r.param;
    simavr_write_ = io.w.c;
    simavr_write_param_ = io.w.param;
    io.r.c = &PhaseCorrectTimer::on_tcnt_read;
    io.r.param = this;
    io.w.c = &PhaseCorrectTimer::on_tcnt_write;
    io.w.param = this;
    reset();
    core_.add_reset_listener(this, [this] { reset(); });
    core_.allow_replay(ReplayableTimer{&PhaseCorrectTimer::on_event, this,
                                       [this](const LoopSpan& span) { return may_replay(span); },
                                       ReplayableTimer::Runs::kAfterJump});
}

PhaseCorrectTimer::~PhaseCorrectTimer() {
    avr_t* avr = core_.raw();
    core_.forget_replay(this);
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(avr, &PhaseCorrectTimer::on_event, this);
    for (uint16_t a : watched_) {
        if (a != 0) core_.unwatch_io(a, &PhaseCorrectTimer::on_register, this, AvrCore::IoReads::kIgnored);
    }
    auto& io = avr->io[AVR_DATA_TO_IO(desc_.tcnt_low)];
    io.r.c = simavr_read_;
    io.r.param = simavr_read_param_;
    io.w.c = simavr_write_;
    io.w.param = simavr_write_param_;
    // simavr's own timers come back with the next register write that
    // reconfigures the timer; a taken-over timer stays quiet until then.
}

bool PhaseCorrectTimer::takes_over(uint8_t wgm) const {
    return wgm < desc_.wgm_modes && sim_->wgm_op[wgm].kind == avr_timer_wgm_none &&
           desc_.modes[wgm].kind == WaveKind::kPhaseCorrect;
}

void PhaseCorrectTimer::reset() {
    // An AVR reset stops the timer and clears its registers without a write
    // notification, and avr_reset wipes the cycle timers.
    decoder_ = TimerOutputDecoder(desc_);
    last_ = read_timer_registers(core_, desc_);
    (void)decoder_.on_write(core_.cycle(), last_, false);
    active_ = false;
    take_or_leave(core_.cycle());
}

void PhaseCorrectTimer::on_register(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    static_cast<PhaseCorrectTimer*>(param)->sample(false);
}

uint8_t PhaseCorrectTimer::on_tcnt_read(avr_t* avr, uint16_t address, void* param) {
    auto* self = static_cast<PhaseCorrectTimer*>(param);
    if (!self->active_) return self->simavr_read_(avr, address, self->simavr_read_param_);
    const uint16_t count = self->decoder_.count_value_at(avr->cycle);
    avr->data[self->desc_.tcnt_low] = static_cast<uint8_t>(count);
    if (self->desc_.tcnt_high != 0) avr->data[self->desc_.tcnt_high] = static_cast<uint8_t>(count >> 8);
    return avr_core_watch_read(avr, address);
}

void PhaseCorrectTimer::on_tcnt_write(avr_t* avr, uint16_t address, uint8_t value, void* param) {
    auto* self = static_cast<PhaseCorrectTimer*>(param);
    // simavr's handler stores the byte (and, in the modes it runs, moves its
    // own count); with TOP taken as 0 it does nothing more.
    self->simavr_write_(avr, address, value, self->simavr_write_param_);
    self->sample(true);
}

void PhaseCorrectTimer::sample(bool tcnt_written) {
    const Cycles now = core_.cycle();
    const TimerRegisters r = read_timer_registers(core_, desc_);
    if (!tcnt_written && same_settings(r, last_)) {
        // A read (simavr notifies those too), the same value again (which
        // in these modes makes simavr arm its own timers again), or ASSR.
        if (active_ != should_take_over()) {
            take_or_leave(now);
        } else if (active_) {
            cancel_simavr_timers();
        }
        return;
    }
    last_ = r;
    (void)decoder_.on_write(now, r, tcnt_written);
    take_or_leave(now);
}

bool PhaseCorrectTimer::should_take_over() const {
    return takes_over(decoder_.wgm()) && decoder_.running() && !clocked_externally();
}

void PhaseCorrectTimer::take_or_leave(Cycles now) {
    active_ = should_take_over();
    if (active_) cancel_simavr_timers();
    reschedule(now);
}

bool PhaseCorrectTimer::clocked_externally() const {
    return (sim_->ext_clock_flags & (AVR_TIMER_EXTCLK_FLAG_TN | AVR_TIMER_EXTCLK_FLAG_AS2)) != 0;
}

void PhaseCorrectTimer::cancel_simavr_timers() {
    avr_t* avr = core_.raw();
    std::vector<avr_cycle_timer_t> fns;
    for (const avr_cycle_timer_slot_t* t = avr->cycle_timers.timer; t != nullptr; t = t->next) {
        if (t->param == sim_ && t->timer != &PhaseCorrectTimer::on_event) fns.push_back(t->timer);
    }
    for (avr_cycle_timer_t fn : fns) avr_cycle_timer_cancel(avr, fn, sim_);
}

void PhaseCorrectTimer::reschedule(Cycles now) {
    avr_t* avr = core_.raw();
    avr_cycle_timer_cancel(avr, &PhaseCorrectTimer::on_event, this);
    if (!active_) return;
    const Cycles next = next_event_after(now);
    if (next != TimerOutputDecoder::kNever) {
        avr_cycle_timer_register(avr, next - avr->cycle, &PhaseCorrectTimer::on_event, this);
    }
}

Cycles PhaseCorrectTimer::next_event_after(Cycles cycle) const {
    // TOP is an event even where it raises no flag: between two events the
    // count then only rises or only falls, so a fast-forward jump bounded by
    // them cannot carry a loop that polls TCNTn past the value it waits for
    // (its verification pass checks only the jump's end).
    Cycles next = std::min({decoder_.next_bottom_after(cycle), decoder_.next_top_after(cycle),
                            decoder_.pending_update_cycle()});
    for (int ch = 0; ch < desc_.channels; ++ch) next = std::min(next, decoder_.next_compare_match_after(ch, cycle));
    return next;
}

uint64_t PhaseCorrectTimer::on_event(avr_t* /*avr*/, uint64_t when, void* param) {
    // `when` is the event's own cycle (after a fast-forward jump the clock is
    // already past it): everything here is computed from it.
    auto* self = static_cast<PhaseCorrectTimer*>(param);
    // The flags first, from the values in effect up to `when`: a new OCRnA
    // or ICR1 taking effect at this TOP moves TOP, but the flag of the TOP
    // reached now is set (7810D §15.9.4).
    self->raise_due(when);
    (void)self->decoder_.advance_to(when);
    const Cycles next = self->next_event_after(when);
    return next == TimerOutputDecoder::kNever ? 0 : next;
}

void PhaseCorrectTimer::raise_due(Cycles when) {
    avr_t* avr = core_.raw();
    const Cycles before = when - 1;
    if (decoder_.next_bottom_after(before) == when) avr_raise_interrupt(avr, &sim_->overflow);
    for (int ch = 0; ch < desc_.channels; ++ch) {
        if (decoder_.next_compare_match_after(ch, before) == when) {
            avr_raise_interrupt(avr, &sim_->comp[ch].interrupt);
        }
    }
    if (decoder_.mode().top_source == TopSource::kIcr && decoder_.next_top_after(before) == when) {
        avr_raise_interrupt(avr, &sim_->icr);
    }
}

bool PhaseCorrectTimer::any_interrupt_enabled() const {
    avr_t* avr = core_.raw();
    if (avr_regbit_get(avr, sim_->overflow.enable) != 0 || avr_regbit_get(avr, sim_->icr.enable) != 0) return true;
    for (int ch = 0; ch < desc_.channels; ++ch) {
        if (avr_regbit_get(avr, sim_->comp[ch].interrupt.enable) != 0) return true;
    }
    return false;
}

bool PhaseCorrectTimer::may_replay(const LoopSpan& span) const {
    if (any_interrupt_enabled()) return false;
    return !span.reads(desc_.tcnt_low) && (desc_.tcnt_high == 0 || !span.reads(desc_.tcnt_high)) &&
           !span.reads(sim_->overflow.raised.reg);
}

PhaseCorrectTimers::PhaseCorrectTimers(AvrCore& core) {
    for (const TimerDesc& d : core.mcu().timers) timers_.push_back(std::make_unique<PhaseCorrectTimer>(core, d));
}

}  // namespace ddmr::hil
