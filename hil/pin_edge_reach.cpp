#include "hil/pin_edge_reach.hpp"

#include <avr_timer.h>
#include <sim_avr.h>

#include "hil/atmega328p.hpp"
#include "hil/board_description.hpp"
#include "hil/fast_forward.hpp"
#include "hil/mcu.hpp"
#include "hil/simavr_io.hpp"

namespace ddmr::hil {

using atmega328p::bit_set;  // a register bit test, the same on every megaAVR

PinEdgeReach::PinEdgeReach(avr_t* avr, const McuDescription& mcu, const PinInfo& pin)
    : pin_register_(pin.pin_register), bit_(static_cast<unsigned>(pin.bit)) {
    if (pin.ext_int) {
        ext_int_ = *pin.ext_int;
        eimsk_ = mcu.eimsk;
        eifr_ = mcu.eifr;
        eicr_ = mcu.eicr_of(ext_int_);
        isc_shift_ = McuDescription::isc_shift(ext_int_);
    }
    if (pin.pcint_group) {
        pcint_group_ = *pin.pcint_group;
        pcint_bit_ = pin.pcint_bit;
        pcicr_ = mcu.pcicr;
        pcifr_ = mcu.pcifr;
        pcmsk_ = static_cast<uint16_t>(mcu.pcmsk0 + pcint_group_);
    }
    // simavr connects a timer's ICP pin to its capture unit (avr_timer.c,
    // avr_timer_reset): the pin's PORT register and bit name it.
    for (avr_io_t* io : simavr_io_modules(avr, "timer")) {
        const auto* t = reinterpret_cast<const avr_timer_t*>(io);
        if (t->icp.reg != 0 && t->icp.reg == pin.port_register && t->icp.bit == pin.bit) captures_.push_back({t});
    }
}

bool PinEdgeReach::replayable(const avr_t* avr, const LoopSpan& span, bool level) const {
    const uint8_t* data = avr->data;
    if (span.reads_bit(pin_register_, bit_)) return false;
    if (ext_int_ >= 0) {
        // A mask or sense bit a pass sets and clears again (plain registers
        // in simavr) would change what an edge inside it does.
        if (span.writes(eimsk_) || span.writes(eicr_)) return false;
        if (bit_set(data[eimsk_], ext_int_) || span.reads(eifr_)) return false;
        const unsigned sense = (data[eicr_] >> isc_shift_) & 3U;
        // Low-level mode: a low sets INTFn only with the I flag set (see the header).
        if (sense == 0 && !level && !bit_set(data[eifr_], ext_int_)) return false;
    }
    if (pcint_group_ >= 0 && (span.writes(pcmsk_) || span.writes(pcicr_))) return false;
    if (pcint_group_ >= 0 && bit_set(data[pcmsk_], pcint_bit_)) {
        if (bit_set(data[pcicr_], pcint_group_) || span.reads(pcifr_)) return false;
    }
    for (const Capture& c : captures_) {
        const auto* t = static_cast<const avr_timer_t*>(c.timer);
        const avr_regbit_t& enable = t->icr.enable;
        if (enable.reg != 0 && (span.writes(enable.reg) || ((data[enable.reg] >> enable.bit) & enable.mask) != 0)) {
            return false;
        }
        if (span.reads(t->icr.raised.reg) || span.reads(t->r_icr) || (t->r_icrh != 0 && span.reads(t->r_icrh))) {
            return false;
        }
    }
    return true;
}

}  // namespace ddmr::hil
