#include "hil/pin_change_restorer.hpp"

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <stdexcept>
#include <string>

namespace ddmr::hil {

PinChangeRestorer::PinChangeRestorer(avr_t* avr, const McuDescription& mcu) : avr_(avr) {
    const std::size_t groups = (mcu.pcint_pins.size() + 7) / 8;
    for (std::size_t g = 0; g < groups; ++g) {
        const int vector = mcu.pcint0_vector + static_cast<int>(g);
        if (avr_get_interrupt_irq(avr_, static_cast<uint8_t>(vector)) != nullptr) continue;  // simavr has it
        auto group = std::make_unique<Group>();
        group->index = static_cast<int>(g);
        group->pcmsk = static_cast<uint16_t>(mcu.pcmsk0 + g);
        group->vector.vector = static_cast<uint8_t>(vector);
        group->vector.enable = avr_regbit_t{mcu.pcicr, static_cast<uint8_t>(g), 1};
        group->vector.raised = avr_regbit_t{mcu.pcifr, static_cast<uint8_t>(g), 1};
        avr_register_vector(avr_, &group->vector);
        for (std::size_t b = 0; b < 8 && 8 * g + b < mcu.pcint_pins.size(); ++b) {
            const auto& pin = mcu.pcint_pins[8 * g + b];
            if (!pin) continue;
            avr_irq_t* irq =
                avr_io_getirq(avr_, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(pin->port)), pin->bit);
            if (irq == nullptr) {
                throw std::runtime_error(std::string("PinChangeRestorer: simavr has no IRQ for pin P") + pin->port +
                                         std::to_string(pin->bit));
            }
            auto watch = std::make_unique<PinWatch>();
            watch->self = this;
            watch->group = group.get();
            watch->mask_bit = static_cast<unsigned>(b);
            watch->level = irq->value != 0;
            avr_irq_register_notify(irq, &PinChangeRestorer::on_pin, watch.get());
            watches_.push_back(std::move(watch));
        }
        groups_.push_back(std::move(group));
    }
}

std::vector<int> PinChangeRestorer::restored_groups() const {
    std::vector<int> out;
    for (const auto& g : groups_) out.push_back(g->index);
    return out;
}

void PinChangeRestorer::on_pin(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* w = static_cast<PinWatch*>(param);
    const bool level = value != 0;
    if (level == w->level) return;  // not a change
    w->level = level;
    const uint8_t mask = w->self->avr_->data[w->group->pcmsk];
    if (((static_cast<unsigned>(mask) >> w->mask_bit) & 1U) == 0) return;
    avr_raise_interrupt(w->self->avr_, &w->group->vector);
}

}  // namespace ddmr::hil
