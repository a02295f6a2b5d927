#include "hil/pin_probe.hpp"

#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <stdexcept>
#include <string>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {

using atmega328p::bit_set;

const char* to_string(PinLevel level) {
    switch (level) {
        case PinLevel::driven_low: return "driven low";
        case PinLevel::driven_high: return "driven high";
        case PinLevel::pulled_up: return "pulled up";
        case PinLevel::floating: return "floating";
    }
    return "?";
}

PinState pin_state(bool ddr_bit, bool port_bit, bool pud) {
    PinState s;
    s.output = ddr_bit;
    s.port_bit = port_bit;
    s.pull_up = !ddr_bit && port_bit && !pud;
    if (ddr_bit) {
        s.level = port_bit ? PinLevel::driven_high : PinLevel::driven_low;
    } else {
        s.level = s.pull_up ? PinLevel::pulled_up : PinLevel::floating;
    }
    return s;
}

PinProbe::PinProbe(AvrCore& core, int pin) : core_(core) {
    const auto info = board_pin(core.board(), pin);
    if (!info) {
        throw std::invalid_argument("PinProbe: board " + std::string(core.board().key) + " has no pin " +
                                    std::to_string(pin) + " (pins " + pin_range(core.board()) + ")");
    }
    info_ = *info;
    const uint16_t registers[] = {info_.ddr_register, info_.port_register, core.mcu().mcucr};
    // sample() compares the pin's state with the last: a notification of an
    // unchanged register (a read, a write of the value it holds) changes
    // nothing. simavr notifies every write of these, a PINx toggle's too.
    for (std::size_t i = 0; i < addresses_.size(); ++i) {
        core_.watch_io(registers[i], &PinProbe::on_register, this, AvrCore::IoReads::kIgnored);
        addresses_[i] = registers[i];
    }
    last_ = state();
    // avr_reset clears DDRx, PORTx and MCUCR without a write notification.
    core_.add_reset_listener(this, [this] { sample(); });
}

PinProbe::~PinProbe() {
    core_.remove_reset_listener(this);
    for (uint16_t a : addresses_) core_.unwatch_io(a, &PinProbe::on_register, this, AvrCore::IoReads::kIgnored);
}

PinState PinProbe::state() const {
    const McuDescription& mcu = core_.mcu();
    return pin_state(bit_set(core_.data(info_.ddr_register), info_.bit),
                     bit_set(core_.data(info_.port_register), info_.bit), bit_set(core_.data(mcu.mcucr), mcu.pud_bit));
}

void PinProbe::on_register(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    static_cast<PinProbe*>(param)->sample();
}

void PinProbe::sample() {
    const PinState now = state();
    if (now == last_) return;  // another pin's bit, or a read (simavr notifies some)
    last_ = now;
    ++changes_;
    if (listener_) listener_(now, core_.cycle());
}

}  // namespace ddmr::hil
