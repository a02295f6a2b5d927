#include "hil/pin_waveforms.hpp"

#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <set>
#include <stdexcept>
#include <string>

#include "hil/avr_timers.hpp"
#include "hil/pin_probe.hpp"
#include "hil/timer_registers.hpp"

namespace ddmr::hil {
namespace {

using atmega328p::bit_set;
using atmega328p::kClockSelectMask;  // CSn2:0 in TCCRnB (every timer here)

}  // namespace

PinWaveforms::PinWaveforms(AvrCore& core, const std::vector<int>& pins)
    : core_(core),
      timers_(core.mcu().timers),
      pin_(static_cast<std::size_t>(core.board().pin_count())),
      timer_(timers_.size()),
      last_regs_(timers_.size()),
      timer_hook_(timers_.size()) {
    std::set<uint16_t> port_registers;
    for (const int p : pins) {
        const auto info = board_pin(core.board(), p);
        if (!info) throw std::invalid_argument("PinWaveforms: no pin " + std::to_string(p));
        Pin& w = pin_[static_cast<std::size_t>(p)];
        w.watched = true;
        w.info = *info;
        port_registers.insert({info->ddr_register, info->port_register, core.mcu().mcucr});
        if (info->oc) {
            const auto t = static_cast<std::size_t>(info->oc->timer);
            if (!timer_[t]) timer_[t].emplace(timers_[t]);
        }
    }
    port_hook_ = Hook{this, -1};
    for (const uint16_t a : port_registers) watch(a, &port_hook_);
    for (std::size_t t = 0; t < timer_.size(); ++t) {
        if (!timer_[t]) continue;
        timer_hook_[t] = Hook{this, static_cast<int>(t)};
        const TimerDesc& d = timers_[t];
        for (const uint16_t a : {d.tccra, d.tccrb, d.ocra_low, d.ocra_high, d.ocrb_low, d.ocrb_high, d.ocrc_low,
                                 d.ocrc_high, d.icr_low, d.icr_high}) {
            if (a != 0) watch(a, &timer_hook_[t]);
        }
        last_regs_[t] = read_timer_registers(core_, d);
        if ((last_regs_[t].tccrb & kClockSelectMask) != 0) {
            // Watched from a running timer on (a query mid-run): its OCR
            // buffers are already in effect on the chip. Take them as a
            // stopped timer takes them (at once), then start its clock.
            TimerRegisters stopped = last_regs_[t];
            stopped.tccrb = static_cast<uint8_t>(stopped.tccrb & ~kClockSelectMask);
            (void)timer_[t]->on_write(core_.cycle(), stopped, false);
        }
        (void)timer_[t]->on_write(core_.cycle(), last_regs_[t], false);
    }
    sample_ports();
    first_change_.reset();
    changes_ = 0;
    // An AVR reset clears the timer and port registers without a write
    // notification: read them again (timers stopped, pins inputs).
    core_.add_reset_listener(this, [this] {
        for (std::size_t t = 0; t < timer_.size(); ++t) {
            if (timer_[t]) sample_timer(t);
        }
        sample_ports();
    });
}

PinWaveforms::~PinWaveforms() { core_.remove_reset_listener(this); }

// sample_ports() and sample_timer() compare with the last state sampled:
// a notification of an unchanged register (a read, a write of the value it
// holds) changes nothing. simavr notifies every write of the ports' and
// timers' registers, a PINx toggle's too (as a PORTx notification).
void PinWaveforms::watch(uint16_t address, Hook* hook) {
    core_.watch_io(address, &PinWaveforms::on_register, hook, AvrCore::IoReads::kIgnored);
}

void PinWaveforms::on_register(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    const auto* hook = static_cast<const Hook*>(param);
    if (hook->timer < 0) {
        hook->self->sample_ports();
    } else {
        hook->self->sample_timer(static_cast<std::size_t>(hook->timer));
    }
}

void PinWaveforms::note_change(Cycles cycle) {
    ++changes_;
    if (!first_change_) first_change_ = cycle;
}

void PinWaveforms::sample_timer(std::size_t t) {
    const TimerRegisters r = read_timer_registers(core_, timers_[t]);
    if (same_settings(r, last_regs_[t])) return;  // simavr also notifies reads
    last_regs_[t] = r;
    ++revision_;
    TimerOutputDecoder& d = *timer_[t];
    const bool was_running = d.running();
    const int channels = timers_[t].channels;
    std::array<bool, kMaxOcChannels> was_connected{};
    for (int c = 0; c < channels; ++c) was_connected[static_cast<std::size_t>(c)] = d.connected(c);
    (void)d.on_write(core_.cycle(), r, false);
    bool changed = d.running() != was_running;
    for (int c = 0; c < channels; ++c) changed = changed || d.connected(c) != was_connected[static_cast<std::size_t>(c)];
    if (changed) {
        note_change(core_.cycle());
    }
    refresh_connections();
}

void PinWaveforms::sample_ports() {
    bool changed = false;
    const bool pud = bit_set(core_.data(core_.mcu().mcucr), core_.mcu().pud_bit);
    for (Pin& p : pin_) {
        if (!p.watched) continue;
        const PinState s = pin_state(bit_set(core_.data(p.info.ddr_register), p.info.bit),
                                     bit_set(core_.data(p.info.port_register), p.info.bit), pud);
        const bool output = s.output;
        // An input's "level" is its pull-up (off under PUD whatever PORT says).
        const bool port = output ? s.port_bit : s.pull_up;
        const PinMode mode = output ? PinMode::output : (s.pull_up ? PinMode::input_pullup : PinMode::input_floating);
        if (mode != p.mode || port != p.port_bit) changed = true;
        p.mode = mode;
        p.port_bit = port;
        p.ever_output = p.ever_output || output;
    }
    if (refresh_connections()) changed = true;
    if (changed) {
        ++revision_;
        note_change(core_.cycle());
        if (port_listener_) port_listener_();
    }
}

bool PinWaveforms::refresh_connections() {
    bool changed = false;
    for (Pin& p : pin_) {
        if (!p.watched) continue;
        const TimerOutputDecoder* t = p.info.oc ? timer_of(p.info.number) : nullptr;
        const bool connected = p.mode == PinMode::output && t != nullptr && t->connected(p.info.oc->channel);
        track_takeover(p, t, connected);
        changed = changed || connected != p.connected;
        p.connected = connected;
    }
    return changed;
}

void PinWaveforms::track_takeover(Pin& p, const TimerOutputDecoder* t, bool connected) {
    if (p.takeover) return;
    const bool without_pwm = connected && t->running() && !t->pwm_mode();
    const Cycles now = core_.cycle();
    if (without_pwm) {
        if (!p.takeover_open) {
            p.takeover_open = Takeover{now, t->wgm(), t->ctc_mode(), timers_[static_cast<std::size_t>(p.info.oc->timer)].index,
                                       static_cast<char>('A' + p.info.oc->channel)};
        }
        return;
    }
    if (p.takeover_open && now - p.takeover_open->since >= kTakeoverMinCycles) p.takeover = p.takeover_open;
    p.takeover_open.reset();
}

std::optional<PinWaveforms::Takeover> PinWaveforms::takeover(int pin) const {
    const Pin& p = pin_[static_cast<std::size_t>(pin)];
    if (p.takeover) return p.takeover;
    if (p.takeover_open && core_.cycle() - p.takeover_open->since >= kTakeoverMinCycles) return p.takeover_open;
    return std::nullopt;
}

void PinWaveforms::advance_to(Cycles cycle) {
    for (auto& t : timer_) {
        if (!t) continue;
        if (const auto applied = t->advance_to(cycle)) {
            ++revision_;
            note_change(*applied);
        }
    }
}

const TimerOutputDecoder* PinWaveforms::timer_of(int pin) const {
    const Pin& p = pin_[static_cast<std::size_t>(pin)];
    if (!p.info.oc) return nullptr;
    const auto& t = timer_[static_cast<std::size_t>(p.info.oc->timer)];
    return t ? &*t : nullptr;
}

bool PinWaveforms::timer_driven(int pin) const { return pin_[static_cast<std::size_t>(pin)].connected; }

bool PinWaveforms::level_at(int pin, Cycles cycle) const {
    const Pin& p = pin_[static_cast<std::size_t>(pin)];
    if (!p.connected) return p.port_bit;
    return timer_[static_cast<std::size_t>(p.info.oc->timer)]->level_at(p.info.oc->channel, cycle);
}

Cycles PinWaveforms::next_change_after(int pin, Cycles cycle) const {
    const Pin& p = pin_[static_cast<std::size_t>(pin)];
    if (!p.connected) return kNever;
    return timer_[static_cast<std::size_t>(p.info.oc->timer)]->next_change_after(p.info.oc->channel, cycle);
}

double PinWaveforms::duty(int pin) const {
    const Pin& p = pin_[static_cast<std::size_t>(pin)];
    if (!p.connected) return p.port_bit ? 1.0 : 0.0;
    return timer_[static_cast<std::size_t>(p.info.oc->timer)]->duty(p.info.oc->channel);
}

}  // namespace ddmr::hil
