#include "hil/adc_input.hpp"

#include <avr_adc.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

#include "hil/atmega328p.hpp"
#include "hil/simavr_io.hpp"

namespace ddmr::hil {
namespace {

using atmega328p::bit_set;

/// simavr 1.6 keeps ADC0..ADC7 only (avr_adc_t::adc_values[8]).
constexpr int kSimavrChannels = 8;
/// ADC8..ADC15 (ATmega2560 2549Q section 26.8.1, Table 26-4).
constexpr int kHighChannels = 16;
/// The largest code, VREF - 1 LSB (section 24.7).
constexpr uint16_t kMaxCode = 1023;
/// ADCSRA bits (section 24.9.2).
constexpr int kAden = 7;
constexpr unsigned kAdpsMask = 0x07;
/// ADMUX REFS1:0 (section 24.9.1).
constexpr unsigned kRefsShift = 6;

/// simavr's ADC module of `avr` (its io list; avr_io_t is avr_adc_t's first member).
avr_adc_t* simavr_adc(avr_t* avr) { return simavr_io_module<avr_adc_t>(avr, "adc"); }

/// The channel a conversion selected: ADC0..7 as simavr reports them, ADC8..15
/// from the entries claim_high_channels rewrote; -1 for anything else.
int selected_channel(const avr_adc_mux_t& mux) {
    if (mux.kind == ADC_MUX_SINGLE && mux.src < kSimavrChannels) return static_cast<int>(mux.src);
    if (mux.kind == ADC_MUX_REF && mux.diff >= kSimavrChannels) return static_cast<int>(mux.diff);
    return -1;
}

uint32_t to_mv(double volts) { return static_cast<uint32_t>(std::lround(volts * 1000.0)); }

/// simavr 1.6's conversion (avr_adc.c, avr_adc_read_l): mV * 1023 / VREF_mV, clipped.
uint32_t simavr_code(uint32_t mv, uint32_t vref_mv) {
    const uint32_t reg = mv * kMaxCode / vref_mv;
    return reg > kMaxCode ? kMaxCode : reg;
}

/// The millivolts simavr turns into `code` against `vref_mv`.
uint32_t simavr_input_mv(uint16_t code, uint32_t vref_mv) {
    if (vref_mv == 0) return 0;
    uint32_t mv = (static_cast<uint32_t>(code) * vref_mv + kMaxCode - 1) / kMaxCode;  // ceil
    // One millivolt is under one LSB for VREF >= 1.023 V; step for smaller ones.
    while (mv > 0 && simavr_code(mv, vref_mv) > code) --mv;
    while (simavr_code(mv, vref_mv) < code) ++mv;
    return mv;
}

}  // namespace

AdcInput::AdcInput(AvrCore& core, const AdcSupply& supply) : core_(core), supply_(supply) {
    if (supply_.avcc_v == 0.0) supply_.avcc_v = core.board().supply_v;
    // Operating range 1.8-5.5 V (section 28.2); VREF 1.0 V .. AVCC (Table 28-8).
    if (!(supply_.avcc_v >= 1.8 && supply_.avcc_v <= 5.5)) {
        throw std::invalid_argument(fmt::format("AdcInput: avcc_v {} V is outside 1.8 .. 5.5 V", supply_.avcc_v));
    }
    if (supply_.aref_v != 0.0 && !(supply_.aref_v >= 1.0 && supply_.aref_v <= supply_.avcc_v)) {
        throw std::invalid_argument(
            fmt::format("AdcInput: aref_v {} V is neither 0 (nothing wired) nor in 1.0 .. {} V (AVCC)", supply_.aref_v,
                        supply_.avcc_v));
    }
    avr_t* avr = core_.raw();
    avr->avcc = to_mv(supply_.avcc_v);
    avr->aref = to_mv(supply_.aref_v);
    for (int n = 0; n < kSimavrChannels; ++n) {
        inputs_[static_cast<std::size_t>(n)] =
            avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_ADC_GETIRQ), ADC_IRQ_ADC0 + n);
    }
    trigger_ = avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_ADC_GETIRQ), ADC_IRQ_OUT_TRIGGER);
    if (trigger_ == nullptr || inputs_[0] == nullptr) {
        throw std::runtime_error(std::string("AdcInput: simavr's ") + core_.mcu().label + " core has no ADC IRQs");
    }
    avr_irq_register_notify(trigger_, &AdcInput::on_trigger, this);
    // A notification of ADCSRA's unchanged value (a read: analogRead()'s
    // wait for ADSC) changes nothing here: ADEN changes only by a write,
    // which this sees, or a reset, which the listener below takes.
    adcsra_ = core_.watch_io(core_.mcu().adc.adcsra, &AdcInput::on_adcsra, this, AvrCore::IoReads::kIgnored);
    aden_ = bit_set(core_.data(core_.mcu().adc.adcsra), kAden);
    if (core_.mcu().adc.channels > kSimavrChannels) claim_high_channels();
    samples_.reserve(kRecordedSamples);
    core_.add_reset_listener(this, [this] {
        // avr_reset clears ADCSRA (ADEN off) and cancels the sample timer.
        aden_ = false;
        next_first_ = true;
        pending_channel_ = -1;
    });
}

AdcInput::~AdcInput() {
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(core_.raw(), &AdcInput::on_sample, this);
    avr_irq_unregister_notify(trigger_, &AdcInput::on_trigger, this);
    core_.unwatch_io(core_.mcu().adc.adcsra, &AdcInput::on_adcsra, this, AvrCore::IoReads::kIgnored);
}

void AdcInput::claim_high_channels() {
    avr_adc_t* adc = simavr_adc(core_.raw());
    if (adc == nullptr) throw std::runtime_error(std::string("AdcInput: simavr's ") + core_.mcu().label + " core has no ADC");
    for (avr_adc_mux_t& entry : adc->muxmode) {
        if (entry.kind == ADC_MUX_REF && entry.diff >= kSimavrChannels && entry.diff < kHighChannels) {
            high_[static_cast<std::size_t>(entry.diff - kSimavrChannels)] = &entry;  // claimed by another AdcInput on this core
            continue;
        }
        if (entry.kind != ADC_MUX_SINGLE || entry.src < kSimavrChannels || entry.src >= kHighChannels) continue;
        const auto channel = static_cast<unsigned>(entry.src);
        entry.kind = ADC_MUX_REF;  // simavr converts src [mV] as it is
        entry.diff = channel & 0xFFU;  // unused by a reference entry: marks the channel
        entry.src = 0;
        high_[channel - kSimavrChannels] = &entry;
    }
    for (int n = kSimavrChannels; n < core_.mcu().adc.channels; ++n) {
        if (high_[static_cast<std::size_t>(n - kSimavrChannels)] == nullptr) {
            throw std::runtime_error(
                fmt::format("AdcInput: simavr's {} core has no mux entry for ADC{}", core_.mcu().label, n));
        }
    }
}

int AdcInput::channel_of(const BoardDescription& board, int pin) {
    const int analog_pins = board.pin_count() - board.analog0 + static_cast<int>(board.analog_only.size());
    const int channel = pin - board.analog0;
    if (channel < 0 || channel >= analog_pins || channel >= board.mcu->adc.channels) {
        throw std::invalid_argument(fmt::format("pin {} of the {} has no ADC input (analog pins A0..A{})", pin,
                                                board.label, analog_pins - 1));
    }
    return channel;
}

void AdcInput::set_voltage(int pin, double volts) {
    set_voltage(pin, [volts](Cycles) { return volts; });
}

void AdcInput::set_voltage(int pin, VoltageFn volts) {
    volts_[static_cast<std::size_t>(channel_of(core_.board(), pin))] = std::move(volts);
}

uint16_t AdcInput::datasheet_code(double vin_v, double vref_v) {
    if (!(vref_v > 0.0) || !(vin_v > 0.0)) return 0;
    const double code = std::floor(vin_v * 1024.0 / vref_v);
    return code >= kMaxCode ? kMaxCode : static_cast<uint16_t>(code);
}

void AdcInput::on_adcsra(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    auto* self = static_cast<AdcInput*>(param);
    const bool aden = bit_set(self->core_.data(self->core_.mcu().adc.adcsra), kAden);
    if (aden && !self->aden_) self->next_first_ = true;
    self->aden_ = aden;
}

void AdcInput::on_trigger(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<AdcInput*>(param);
    avr_adc_mux_t mux{};
    std::memcpy(&mux, &value, sizeof(value));  // simavr sends the struct's low 32 bits
    // This write may be the one that sets ADEN (its notification comes after).
    const bool first = self->next_first_ || !self->aden_;
    self->next_first_ = false;
    self->aden_ = true;
    const int channel = selected_channel(mux);
    if (channel < 0) return;
    if (!self->volts_[static_cast<std::size_t>(channel)]) return;
    // Sample-and-hold 1.5 ADC clocks after the start, 13.5 for a first
    // conversion (Table 24-1); the ADC clock is F_CPU / 2^ADPS (ADPS 0 -> /2).
    const unsigned adps = self->core_.data(self->core_.mcu().adc.adcsra) & kAdpsMask;
    const Cycles prescaler = Cycles{1} << (adps == 0 ? 1 : adps);
    const Cycles delay = (first ? 27 : 3) * prescaler / 2;
    self->pending_channel_ = channel;
    self->pending_start_ = self->core_.cycle();
    avr_cycle_timer_cancel(self->core_.raw(), &AdcInput::on_sample, self);
    avr_cycle_timer_register(self->core_.raw(), delay, &AdcInput::on_sample, self);
}

uint64_t AdcInput::on_sample(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<AdcInput*>(param);
    // `when` is the sample-and-hold cycle itself; simavr runs the timer at
    // the first instruction boundary at or after it (the value lands in
    // simavr's input long before the conversion ends and the firmware reads it).
    if (self->pending_channel_ >= 0) self->sample(self->pending_channel_, self->pending_start_, when);
    self->pending_channel_ = -1;
    return 0;
}

void AdcInput::reference(double& vref_v, uint32_t& simavr_mv) const {
    const AdcDesc& adc = core_.mcu().adc;
    const unsigned refs = (static_cast<unsigned>(core_.data(adc.admux)) >> kRefsShift) & 3U;
    const AdcRefChoice& choice = adc.refs[refs];
    switch (choice.kind) {
        case AdcRefKind::avcc:
            vref_v = supply_.avcc_v;
            break;
        case AdcRefKind::internal:
            vref_v = choice.internal_v;
            break;
        case AdcRefKind::aref:
        case AdcRefKind::reserved:  // simavr 1.6 reads AREF there
            vref_v = supply_.aref_v;
            break;
    }
    simavr_mv = to_mv(vref_v);
}

void AdcInput::sample(int channel, Cycles start, Cycles at) {
    AdcSample s;
    s.channel = channel;
    s.start_cycle = start;
    s.sample_cycle = at;
    s.vin_v = volts_[static_cast<std::size_t>(channel)](s.sample_cycle);
    uint32_t vref_mv = 0;
    reference(s.vref_v, vref_mv);
    s.code = datasheet_code(s.vin_v, s.vref_v);
    const uint32_t mv = simavr_input_mv(s.code, vref_mv);
    if (channel < kSimavrChannels) {
        avr_raise_irq(inputs_[static_cast<std::size_t>(channel)], mv);
    } else {
        // Read back at ADCL; the 13-bit field holds up to 8191 mV (AVCC <= 5.5 V).
        high_[static_cast<std::size_t>(channel - kSimavrChannels)]->src = mv & 0x1FFFU;
    }
    ++conversions_;
    if (samples_.size() < kRecordedSamples) samples_.push_back(s);
}

}  // namespace ddmr::hil
