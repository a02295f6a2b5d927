#pragma once
// SquareWaveInput: toggles one input pin every `half_period` cycles, so the
// reference firmware's CHANGE interrupts count one edge per toggle without a
// plant. Tests use it on pins 2 and 3 (PD2, PD3: Count1, Count2) to give the
// firmware a known, steady "wheel speed" and so non-zero positions.
#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <cstdint>
#include <stdexcept>

#include "hil/avr_core.hpp"

namespace ddmr::test {

class SquareWaveInput {
public:
    /// Starts now: the first toggle (a rising edge) comes `half_period` cycles later.
    SquareWaveInput(hil::AvrCore& core, char port, int pin, hil::Cycles half_period)
        : core_(core), half_period_(half_period) {
        irq_ = avr_io_getirq(core.raw(), static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(port)), pin);
        if (irq_ == nullptr || half_period == 0) throw std::invalid_argument("SquareWaveInput");
        avr_cycle_timer_register(core.raw(), half_period_, &SquareWaveInput::on_toggle, this);
    }
    ~SquareWaveInput() { avr_cycle_timer_cancel(core_.raw(), &SquareWaveInput::on_toggle, this); }
    SquareWaveInput(const SquareWaveInput&) = delete;
    SquareWaveInput& operator=(const SquareWaveInput&) = delete;

    uint64_t edges() const { return edges_; }

private:
    static avr_cycle_count_t on_toggle(avr_t* /*avr*/, avr_cycle_count_t when, void* param) {
        auto* self = static_cast<SquareWaveInput*>(param);
        self->level_ ^= 1U;
        avr_raise_irq(self->irq_, self->level_);
        ++self->edges_;
        return when + self->half_period_;
    }

    hil::AvrCore& core_;
    hil::Cycles half_period_;
    avr_irq_t* irq_ = nullptr;
    uint32_t level_ = 0;
    uint64_t edges_ = 0;
};

}  // namespace ddmr::test
