#include "hil/encoder_injector.hpp"

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_io.h>
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

EncoderInjector::EncoderInjector(AvrCore& core, const BoardWiring& board) : core_(core) {
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
            sig.irq = avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(sig.pin.port)), sig.pin.bit);
            if (sig.irq == nullptr) throw std::runtime_error("simavr has no IRQ for pin " + std::to_string(w.pin[s]));
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
    core_.add_reset_listener(this, [this] { restore_after_reset(); });
}

EncoderInjector::~EncoderInjector() {
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(core_.raw(), &EncoderInjector::on_timer, this);
}

void EncoderInjector::restore_after_reset() {
    // An AVR reset cancels the edge timer and clears PINx; the sensors still
    // drive their pins: restore the levels and re-arm for the queued edges.
    for (const auto& wheel : signal_) {
        for (const Signal& s : wheel) {
            if (!s.used) continue;
            uint8_t& pin = core_.raw()->data[s.pin.pin_register];
            const auto mask = static_cast<uint8_t>(1U << static_cast<unsigned>(s.pin.bit));
            pin = s.irq->value != 0 ? static_cast<uint8_t>(pin | mask) : static_cast<uint8_t>(pin & ~mask);
        }
    }
    armed_ = false;
    if (!queue_.empty()) {
        const Cycles now = core_.cycle();
        const Cycles at = queue_.front().cycle;
        armed_ = true;
        avr_cycle_timer_register(core_.raw(), at > now ? at - now : 0, &EncoderInjector::on_timer, this);
    }
}

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
    return s.used && s.irq->value != 0;
}

void EncoderInjector::drive_now(unsigned channel, unsigned signal, bool level) {
    const Signal& s = signal_[channel][pin_index(channel, signal)];
    if (!s.used) throw std::out_of_range("encoder signal not wired");
    avr_raise_irq(s.irq, level ? 1 : 0);
}

void EncoderInjector::schedule(unsigned channel, unsigned signal, Cycles cycle, bool level) {
    if (!signal_[channel][pin_index(channel, signal)].used) return;  // the wheel has no such output
    queue_.push_back(Edge{cycle, channel, pin_index(channel, signal), level});
    if (!armed_) {
        const Cycles now = core_.cycle();
        armed_ = true;
        avr_cycle_timer_register(core_.raw(), cycle > now ? cycle - now : 0, &EncoderInjector::on_timer, this);
    }
}

uint64_t EncoderInjector::on_timer(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<EncoderInjector*>(param);
    while (!self->queue_.empty() && self->queue_.front().cycle <= when) {
        self->raise(self->queue_.front());
        self->queue_.pop_front();
    }
    if (self->queue_.empty()) {
        self->armed_ = false;
        return 0;
    }
    return self->queue_.front().cycle;
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

void EncoderInjector::raise(const Edge& e) {
    EncoderChannelStats& st = stats_[e.channel];
    const Signal& s = signal_[e.channel][e.signal];
    if (request_pending(s, e.level)) {
        ++st.lost_edges;
        st.last_lost_cycle = core_.cycle();
    }
    ++st.edges_injected;
    avr_raise_irq(s.irq, e.level ? 1 : 0);
    if (edge_listener_) edge_listener_(s.pin.number, core_.cycle(), e.level);
}

}  // namespace ddmr::hil
