#pragma once
// PinProbe: what the firmware has made of one board pin, as the datasheet
// defines it (ATmega328P 7810D section 13.2.1 "Configuring the Pin",
// Table 13-1 "Port Pin Configurations"; ATmega2560 2549Q 13.2.1, the same
// table):
//
//   DDxn PORTxn PUD | I/O    pull-up | what an external part sees
//    0     0     X  | input  no      | floating (tri-state, Hi-Z)
//    0     1     0  | input  yes     | pulled up (20-50 kOhm to VCC, 28.2 RPU)
//    0     1     1  | input  no      | floating
//    1     0     X  | output no      | driven low (sink)
//    1     1     X  | output no      | driven high (source)
//
// PUD is bit 4 of MCUCR (section 13.4.1). An output whose timer's
// compare-output unit is connected (COMnx bits) shows the waveform instead of
// PORTxn: that is PinWaveforms' business (hil/pin_waveforms.hpp); this probe
// reports the pin's mode.
//
// Signals (simavr iomem notifications, after each access): DDRx, PORTx (also
// raised by simavr when a write of 1 to PINx toggles PORTx) and MCUCR. A
// listener is called with the new state and the cycle when the state changes;
// an AVR reset (all pins inputs, pull-ups off) is a change too.
//
// simavr 1.6 itself does not model PUD: with PUD set, it still raises an
// input pin whose PORT bit is 1 to level 1. This probe reports the datasheet's
// "floating"; what the firmware then reads from the pin is undefined on the
// chip (section 13.2.6 "Unconnected Pins").
// Not thread-safe (like AvrCore). Construct after the AvrCore, destroy before.

#include <array>
#include <cstdint>
#include <functional>

#include "hil/avr_core.hpp"
#include "hil/board_description.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// What a part connected to the pin sees (Table 13-1).
enum class PinLevel : uint8_t { driven_low, driven_high, pulled_up, floating };
const char* to_string(PinLevel level);

/// A pin's configuration (Table 13-1).
struct PinState {
    bool output = false;    ///< DDxn = 1
    bool port_bit = false;  ///< PORTxn: the output level, or the pull-up request of an input
    bool pull_up = false;   ///< the pull-up is on: input, PORTxn = 1 and PUD = 0
    PinLevel level = PinLevel::floating;
    bool operator==(const PinState& o) const {
        return output == o.output && port_bit == o.port_bit && pull_up == o.pull_up && level == o.level;
    }
    bool operator!=(const PinState& o) const { return !(*this == o); }
};

/// Table 13-1 from the three register bits.
PinState pin_state(bool ddr_bit, bool port_bit, bool pud);

class PinProbe {
public:
    /// The new state and the AVR cycle of the register write that made it.
    using Listener = std::function<void(const PinState&, Cycles)>;

    /// Watches board pin `pin`; throws std::invalid_argument naming the pin
    /// if the board has no such digital pin.
    PinProbe(AvrCore& core, int pin);
    ~PinProbe();
    PinProbe(const PinProbe&) = delete;
    PinProbe& operator=(const PinProbe&) = delete;

    [[nodiscard]] int pin() const { return info_.number; }
    /// The state as the registers hold it now.
    [[nodiscard]] PinState state() const;
    /// `listener` is called on each change from now on (nullptr: none). Keep
    /// it short; it runs inside the firmware's register write and must not throw.
    void set_listener(Listener listener) { listener_ = std::move(listener); }
    /// State changes seen since construction.
    [[nodiscard]] uint64_t changes() const { return changes_; }

private:
    static void on_register(avr_irq_t* irq, uint32_t value, void* param);
    void sample();

    AvrCore& core_;
    PinInfo info_{};
    std::array<uint16_t, 3> addresses_{};  ///< DDRx, PORTx, MCUCR (data addresses), watched
    PinState last_{};
    Listener listener_;
    uint64_t changes_ = 0;
};

}  // namespace ddmr::hil
