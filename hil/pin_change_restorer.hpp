#pragma once
// PinChangeRestorer: the pin-change interrupt groups an MCU has
// (McuDescription::pcint_pins) but simavr's core does not declare, restored
// as the datasheet defines them. simavr 1.6's ATmega2560 core declares only
// PCINT0 (port B); PCINT1 (PE0, PJ0..PJ6) and PCINT2 (PK0..PK7, the Mega's
// A8..A15) never fire there.
//
// ATmega2560 datasheet 2549Q, 15.2.5..15.2.8 (PCICR, PCIFR, PCMSK0..2): any
// level change on a pin whose PCMSKn bit is set sets PCIFn; with PCIEn set
// in PCICR the PCINTn vector is requested. The restorer registers each
// missing vector with simavr (enable = PCICR.PCIEn, flag = PCIFR.PCIFn, so
// simavr serves and clears it as its own) and raises it from the pins' IRQs:
// edges the HIL drives (encoders) and the firmware's own output changes.
// The datasheet's 2-cycle pin synchroniser is not modelled (simavr's PCINT0
// has none either).
//
// Owned by AvrCore; it must outlive simavr's avr_t (simavr keeps pointers to
// the vectors), and leaves the hooks to die with it.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include <sim_interrupts.h>

#include "hil/mcu.hpp"

struct avr_t;
struct avr_irq_t;

namespace ddmr::hil {

class PinChangeRestorer {
public:
    /// Restores every pin-change group of `mcu` whose vector `avr` lacks.
    PinChangeRestorer(avr_t* avr, const McuDescription& mcu);
    PinChangeRestorer(const PinChangeRestorer&) = delete;
    PinChangeRestorer& operator=(const PinChangeRestorer&) = delete;

    /// The group numbers n (PCINTn vectors) restored: {1, 2} on the ATmega2560.
    [[nodiscard]] std::vector<int> restored_groups() const;

private:
    struct Group {
        int index = 0;
        uint16_t pcmsk = 0;  ///< PCMSKn's data address
        avr_int_vector_t vector{};
    };
    struct PinWatch {
        PinChangeRestorer* self = nullptr;
        Group* group = nullptr;
        unsigned mask_bit = 0;  ///< the pin's bit in PCMSKn
        bool level = false;     ///< last level seen
    };
    static void on_pin(avr_irq_t* irq, uint32_t value, void* param);

    avr_t* avr_;
    std::vector<std::unique_ptr<Group>> groups_;  ///< stable addresses: simavr keeps pointers
    std::vector<std::unique_ptr<PinWatch>> watches_;
};

}  // namespace ddmr::hil
