#include "hil/encoder_injector.hpp"

#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <stdexcept>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

using atmega328p::bit_set;

/// ISCn1:0 in EICRA/EICRB (datasheet Table 12-2): 0 low level, 1 any change, 2 falling, 3 rising.
enum class Sense : uint8_t { low_level = 0, change = 1, falling = 2, rising = 3 };

}  // namespace

EncoderInjector::EncoderInjector(AvrCore& core, const BoardWiring& board) : core_(core), driver_(core) {
    validate(board);
    if (board.model != core.board().model) {
        throw std::logic_error(std::string("EncoderInjector: the wiring is for board ") +
                               board_description(board.model).key + ", the core runs " + core.board().key);
    }
    avr_t* avr = core_.raw();
    const McuDescription& mcu = core_.mcu();
    for (unsigned ch = 0; ch < 2; ++ch) {
        const EncoderWiring& w = board.wheel[ch].encoder;
        for (unsigned s = 0; s < w.signals(); ++s) {
            Signal& sig = signal_[ch][s];
            sig.used = true;
            sig.pin = *board_pin(core_.board(), w.pin[s]);
            // A pin with neither (some Mega pins) can only be polled: no vector.
            if (sig.pin.ext_int) {
                sig.vector = mcu.int0_vector + *sig.pin.ext_int;
            } else if (sig.pin.pcint_group) {
                sig.vector = mcu.pcint0_vector + *sig.pin.pcint_group;
            }
            // simavr's own "request pending" state of each vector the pin can
            // raise (1 from the request until the vector is served); the
            // flag registers cannot tell it: simavr 1.6 does not clear EIFR /
            // PCIFR flags written with 1, as the chip does.
            const auto pending_of = [&](int vector) {
                avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(vector));
                // AvrCore declares every vector simavr's core lacks (PinChangeRestorer).
                if (irqs == nullptr) {
                    throw std::logic_error(fmt::format("encoder pin {}: simavr's {} core declares no vector {}",
                                                       w.pin[s], core_.mcu().label, core_.mcu().vector_name(vector)));
                }
                return irqs + AVR_INT_IRQ_PENDING;
            };
            if (sig.pin.ext_int) sig.ext_pending = pending_of(mcu.int0_vector + *sig.pin.ext_int);
            if (sig.pin.pcint_group) sig.pcint_pending = pending_of(mcu.pcint0_vector + *sig.pin.pcint_group);
        }
        swapped_[ch] = w.kind == EncoderKind::quadrature && w.reversed;
        // No encoder on this wheel (its edges go nowhere), or a polled pin: no ISR to count.
        if (signal_[ch][0].vector < 0) continue;
        isr_entries_[ch].reserve(kRecordedIsrEntries);
        avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(signal_[ch][0].vector));
        if (irqs == nullptr) throw std::runtime_error("simavr has no IRQ for vector " + std::to_string(signal_[ch][0].vector));
        isr_watch_[ch] = IsrWatch{this, ch};
        avr_irq_register_notify(irqs + AVR_INT_IRQ_RUNNING, &EncoderInjector::on_isr, &isr_watch_[ch]);
    }
    driver_.set_before_edge([this](int pin, Cycles cycle, bool level) { before_edge(pin, cycle, level); });
    driver_.set_after_edge([this](int pin, Cycles cycle, bool level) {
        if (edge_listener_) edge_listener_(pin, cycle, level);
    });
}

EncoderInjector::~EncoderInjector() = default;

void EncoderInjector::on_isr(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    if (value == 0) return;  // 0: RETI; 1: the vector is entered
    const auto* watch = static_cast<const IsrWatch*>(param);
    EncoderInjector* self = watch->self;
    auto& entries = self->isr_entries_[watch->channel];
    if (entries.size() < kRecordedIsrEntries) entries.push_back(self->core_.cycle());  // memory stays flat
    ++self->stats_[watch->channel].isr_count;
}

unsigned EncoderInjector::pin_index(unsigned channel, unsigned signal) const {
    return swapped_[channel] ? 1U - signal : signal;
}

bool EncoderInjector::level(unsigned channel, unsigned signal) const {
    const Signal& s = signal_[channel][signal];
    return s.used && driver_.level(s.pin.number);
}

void EncoderInjector::drive_now(unsigned channel, unsigned signal, bool level) {
    const Signal& s = signal_[channel][pin_index(channel, signal)];
    if (!s.used) throw std::out_of_range("encoder signal not wired");
    driver_.drive_now(s.pin.number, level);
}

void EncoderInjector::schedule(unsigned channel, unsigned signal, Cycles cycle, bool level) {
    const Signal& s = signal_[channel][pin_index(channel, signal)];
    if (!s.used) return;  // the wheel has no such output
    driver_.schedule(s.pin.number, cycle, level);
}

bool EncoderInjector::request_pending(const Signal& s, bool level) const {
    const McuDescription& mcu = core_.mcu();
    if (s.pin.ext_int) {
        const int n = *s.pin.ext_int;
        if (!bit_set(core_.data(mcu.eimsk), n)) return false;
        const auto sense =
            static_cast<Sense>((static_cast<unsigned>(core_.data(mcu.eicr_of(n))) >> McuDescription::isc_shift(n)) & 3U);
        // Low level has no latch (the request lasts while the pin is low);
        // an edge of the other polarity requests nothing.
        const bool requests = sense == Sense::change || (sense == Sense::rising && level) ||
                              (sense == Sense::falling && !level);
        if (requests && s.ext_pending->value != 0) return true;
    }
    if (!s.pin.pcint_group) return false;
    const int g = *s.pin.pcint_group;
    if (!bit_set(core_.data(static_cast<uint16_t>(mcu.pcmsk0 + g)), s.pin.pcint_bit)) return false;
    if (!bit_set(core_.data(mcu.pcicr), g)) return false;
    return s.pcint_pending->value != 0;
}

void EncoderInjector::before_edge(int pin, Cycles cycle, bool level) {
    for (unsigned ch = 0; ch < 2; ++ch) {
        for (const Signal& s : signal_[ch]) {
            if (!s.used || s.pin.number != pin) continue;
            EncoderChannelStats& st = stats_[ch];
            if (request_pending(s, level)) {
                ++st.lost_edges;
                st.last_lost_cycle = cycle;
            }
            ++st.edges_injected;
            return;
        }
    }
}

}  // namespace ddmr::hil
