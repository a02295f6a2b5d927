#pragma once
// TimerEventReach: what one of simavr's timer cycle timers does when it
// runs, so that fast-forward may run it after a jump, at its own cycle,
// instead of ending the jump before it (hil/fast_forward.hpp). A kit
// robot's PWM (analogWrite() on Timer0's D5/D6, a 20 kHz Timer1 on D9/D10)
// changes its OC pins two to four times a PWM period: each change would
// otherwise bound a jump.
//
// simavr 1.6 (sim/avr_timer.c) arms, per timer clocked from the prescaler:
// - the overflow's callback, due at tov_base + tov_cycles. It sets TOVn
//   (the overflow interrupt if TOIEn is set); in every PWM mode each
//   compare unit's OC output goes to its level at BOTTOM (COMnx "clear on
//   compare match" sets it, "set" clears it: avr_timer_comp_on_tov); a unit
//   whose compare falls at TOP (comp_cycles == tov_cycles) is run from it;
//   the others' callbacks are armed (due inside a jump, they run in its
//   replay too: the overflow is replayable only with all its units);
// - compare unit x's callback, due at tov_base + comp_cycles. It sets OCFnx
//   (the interrupt if OCIEnx is set) and, by COMnx (datasheet ATmega328P
//   7810D 14.7 / 15.9 / 17.7 "Modes of Operation"), clears, sets or toggles
//   OCnx. Clear and set raise the pin's IRQ: the pin's PIN bit, its pin-
//   change interrupt, INTn, an input capture (hil/pin_edge_reach.hpp).
//   Toggle also writes the PORT register (AVR_IOPORT_OUTPUT): never replayed.
// Which callback a pending cycle timer is follows from when it is due.
// Run later at its own cycle, it leaves the same state, provided the passes
// skipped use nothing it changes (TCNTn, which simavr computes from the last
// overflow's cycle, for the overflow's; the flag it sets, by the bits a pass
// uses of TIFRn: hil/io_bit_use.hpp), nor what its OC pins' edges reach, and
// neither read their PIN register nor write their PORT or DDR register: a
// read of PINx stores PORTx's bits into PINx's output bits (avr_ioport_read),
// a write raises every output pin with its PORT bit, over the OC level
// (avr_ioport_update_irqs); and it requests no interrupt.
//
// Reads the registers when asked; holds simavr's timer module (owned by the
// avr_t, which outlives fast-forward).

#include <array>
#include <cstdint>
#include <optional>

#include "hil/cycle_time.hpp"
#include "hil/pin_edge_reach.hpp"

struct avr_t;

namespace ddmr::hil {

struct BoardDescription;
struct LoopSpan;
struct McuDescription;

class TimerEventReach {
public:
    /// `timer`: simavr's avr_timer_t. OC pins the board does not bring out
    /// are never replayed.
    TimerEventReach(avr_t* avr, const McuDescription& mcu, const BoardDescription& board, const void* timer);

    /// True if the timer's callback due at `when`, run after passes that
    /// access the I/O in `span` instead of among them, gives the same state.
    [[nodiscard]] bool replayable(Cycles when, const LoopSpan& span) const;

    static constexpr std::size_t kUnits = 3;  ///< compare units A, B, C (AVR_TIMER_COMP_COUNT)

private:
    struct OcPin {
        PinEdgeReach reach;
        uint16_t pin_register = 0;
        uint16_t port_register = 0;
        uint16_t ddr_register = 0;
    };
    [[nodiscard]] bool overflow_replayable(const LoopSpan& span) const;
    [[nodiscard]] bool compare_replayable(std::size_t unit, const LoopSpan& span) const;
    [[nodiscard]] bool oc_edges_replayable(std::size_t unit, const LoopSpan& span) const;

    const avr_t* avr_;
    const void* timer_;
    std::array<std::optional<OcPin>, kUnits> oc_{};
};

}  // namespace ddmr::hil
