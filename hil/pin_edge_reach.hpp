#pragma once
// PinEdgeReach: what an edge a part puts on an input pin can reach inside
// the chip, so that fast-forward may raise it after a jump, at its own
// cycle, instead of ending the jump before it (hil/fast_forward.hpp,
// ReplayableTimer). A kit robot's encoders are often wired and never read
// (a line follower's): their edges, thousands a second, would otherwise
// bound every jump.
//
// An edge on a pin (datasheet ATmega328P, 7810D; the ATmega2560's INT4-7,
// PCINT groups and timers alike) reaches:
// - PINx: the level the firmware reads (13.2.4 "Reading the Pin Value");
// - INTn, if the pin carries one: the sense bits ISCn1:0 decide whether the
//   edge sets INTFn in EIFR, and the interrupt is requested if INTn is
//   enabled in EIMSK (12.1, 12.2.1-12.2.3). simavr 1.6 (avr_extint.c) sets
//   INTFn on a low level only while the I flag is set and INTFn is clear:
//   such an edge depends on the I flag at its instruction boundary, which a
//   skipped pass may toggle (micros()), so it is not replayed;
// - PCINTk, if its PCMSKn bit is set: PCIFn in PCIFR, and the interrupt if
//   PCIEn is set in PCICR (12.2.4-12.2.8);
// - the input capture unit of a timer whose ICPn is the pin: ICRn and ICFn
//   in TIFRn, and the interrupt if ICIEn is set (16.6 "Input Capture Unit").
// Raised later at its own cycle (the core's clock set there), the edge
// leaves the same state, provided the passes read neither the pin nor a
// flag or capture register it sets, and it requests no interrupt. A pass
// that reads the PIN register but uses other bits of it only (digitalRead()
// of another pin of the port: hil/io_bit_use.hpp) does not read the pin.
//
// Reads the registers when asked; holds simavr's timer modules (owned by
// the avr_t, which outlives the parts).

#include <cstdint>
#include <vector>

struct avr_t;

namespace ddmr::hil {

struct LoopSpan;
struct McuDescription;
struct PinInfo;

class PinEdgeReach {
public:
    PinEdgeReach() = default;
    PinEdgeReach(avr_t* avr, const McuDescription& mcu, const PinInfo& pin);

    /// True if an edge to `level` raised during passes that read the I/O in
    /// `span`, at the jump's end instead, gives the same state: no interrupt
    /// it may request is enabled, the passes read neither the pin nor what it
    /// may set, and (on an INTn pin in low-level mode) it sets no flag.
    [[nodiscard]] bool replayable(const avr_t* avr, const LoopSpan& span, bool level) const;

private:
    struct Capture {
        const void* timer;  ///< simavr's avr_timer_t
    };
    uint16_t pin_register_ = 0;
    unsigned bit_ = 0;  ///< the pin's bit in it
    int ext_int_ = -1;
    uint16_t eimsk_ = 0, eifr_ = 0, eicr_ = 0;
    unsigned isc_shift_ = 0;
    int pcint_group_ = -1;
    int pcint_bit_ = 0;
    uint16_t pcicr_ = 0, pcifr_ = 0, pcmsk_ = 0;
    std::vector<Capture> captures_;
};

}  // namespace ddmr::hil
