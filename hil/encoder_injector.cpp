#include "hil/encoder_injector.hpp"

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_interrupts.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <stdexcept>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

int vector_of(int external_interrupt) {
    return external_interrupt == 0 ? atmega328p::vector::kInt0 : atmega328p::vector::kInt1;
}

}  // namespace

EncoderInjector::EncoderInjector(AvrCore& core, const BoardWiring& board) : core_(core) {
    validate(board, "board");
    avr_t* avr = core_.raw();
    for (unsigned ch = 0; ch < 2; ++ch) {
        const int pin = board.encoder[ch].pin;
        const PinLocation loc = *uno_pin_location(pin);
        pin_irq_[ch] = avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(loc.port)), loc.bit);
        if (pin_irq_[ch] == nullptr) {
            throw std::runtime_error("simavr has no IRQ for pin " + std::to_string(pin));
        }
        interrupt_[ch] = uno_external_interrupt(pin);
        isr_entries_[ch].reserve(kRecordedIsrEntries);
        if (interrupt_[ch]) {
            avr_irq_t* irqs = avr_get_interrupt_irq(avr, static_cast<uint8_t>(vector_of(*interrupt_[ch])));
            if (irqs == nullptr) throw std::runtime_error("simavr has no IRQ for INT" + std::to_string(*interrupt_[ch]));
            isr_watch_[ch] = IsrWatch{this, ch};
            avr_irq_register_notify(irqs + AVR_INT_IRQ_RUNNING, &EncoderInjector::on_isr, &isr_watch_[ch]);
        }
        pin_register_[ch] = static_cast<uint16_t>(loc.port_register - 2);  // PINx = PORTx - 2
        pin_bit_[ch] = loc.bit;
    }
    // An AVR reset cancels the edge timer and clears PINx; the sensors still
    // drive their pins: restore the levels and re-arm for the queued edges.
    core_.add_reset_listener(this, [this] {
        for (unsigned ch = 0; ch < 2; ++ch) {
            uint8_t& pin = core_.raw()->data[pin_register_[ch]];
            const auto mask = static_cast<uint8_t>(1U << pin_bit_[ch]);
            pin = pin_irq_[ch]->value != 0 ? static_cast<uint8_t>(pin | mask) : static_cast<uint8_t>(pin & ~mask);
        }
        armed_ = false;
        if (!queue_.empty()) {
            const Cycles now = core_.cycle();
            const Cycles at = queue_.front().cycle;
            armed_ = true;
            avr_cycle_timer_register(core_.raw(), at > now ? at - now : 0, &EncoderInjector::on_timer, this);
        }
    });
}

EncoderInjector::~EncoderInjector() {
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(core_.raw(), &EncoderInjector::on_timer, this);
}

void EncoderInjector::on_isr(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    if (value == 0) return;  // 0: RETI; 1: the vector is entered
    const auto* watch = static_cast<const IsrWatch*>(param);
    EncoderInjector* self = watch->self;
    auto& entries = self->isr_entries_[watch->channel];
    if (entries.size() < kRecordedIsrEntries) entries.push_back(self->core_.cycle());  // memory stays flat
    ++self->stats_[watch->channel].isr_count;
}

void EncoderInjector::schedule(unsigned channel, Cycles cycle, bool level) {
    queue_.push_back(Edge{cycle, channel, level});
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

void EncoderInjector::raise(const Edge& e) {
    EncoderChannelStats& s = stats_[e.channel];
    if (interrupt_[e.channel]) {
        const unsigned flag = 1U << static_cast<unsigned>(*interrupt_[e.channel]);
        if ((core_.data(atmega328p::reg::kEifr) & flag) != 0) {
            ++s.lost_edges;
            s.last_lost_cycle = core_.cycle();
        }
    }
    ++s.edges_injected;
    avr_raise_irq(pin_irq_[e.channel], e.level ? 1 : 0);
    if (edge_listener_) edge_listener_(e.channel, core_.cycle(), e.level);
}

}  // namespace ddmr::hil
