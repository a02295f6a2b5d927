#pragma once
// The ATmega328P's pins as the Arduino Uno and Nano number them, as data:
// for each silkscreen pin its port and bit, its PINx/DDRx/PORTx registers,
// the timer output-compare unit on it, its external interrupt and its
// pin-change interrupt group. One table, read by every part that touches a
// pin (driver inputs, encoder outputs, VCD, scenario pin checks).
//
// Sources: ATmega328P datasheet 7810D, Figure 1-1 (pinout), Table 11-1
// (vectors), section 12 (EICRA/EIMSK/EIFR, PCICR/PCIFR/PCMSKn); the Arduino
// core's variants/standard/pins_arduino.h (D0-D7 = PD0-PD7, D8-D13 =
// PB0-PB5, A0-A5 = D14-D19 = PC0-PC5; digitalPinToInterrupt: D2 -> 0, D3 -> 1).
// The Nano's A6/A7 are ADC-only inputs with no port bit: not digital pins.

#include <cstdint>
#include <optional>
#include <string>

namespace ddmr::hil {

/// Digital pins of the Uno/Nano: D0..D13 and A0..A5 (= 14..19).
inline constexpr int kUnoPinCount = 20;

/// A timer output-compare channel: timer 0, 1 or 2, channel 0 = A, 1 = B.
struct OcChannel {
    int timer = 0;
    int channel = 0;
};

struct UnoPin {
    int number = 0;              ///< 0..19
    char port = 'D';             ///< 'B', 'C' or 'D'
    int bit = 0;                 ///< 0..7
    uint16_t pin_register = 0;   ///< PINx data-space address (input level)
    uint16_t ddr_register = 0;   ///< DDRx (1 = output)
    uint16_t port_register = 0;  ///< PORTx (output level, or the pull-up of an input)
    std::optional<OcChannel> oc;       ///< OCnx on this pin (the six PWM pins)
    std::optional<int> ext_int;        ///< 0 (INT0, D2) or 1 (INT1, D3)
    int pcint_group = 0;               ///< PCIEn / PCIFn / PCMSKn index: 0 port B, 1 port C, 2 port D
    int pcint_bit = 0;                 ///< bit in PCMSKn (= the port bit)
};

/// The pin's description, or nullopt when the board has no such digital pin.
std::optional<UnoPin> uno_pin(int number);

/// "5", "D5", "A0".."A5", "14".."19" -> pin number; nullopt if not a pin name.
std::optional<int> parse_uno_pin_name(const std::string& name);

/// Silkscreen name: 0..13 as "D13", 14..19 as "A0".."A5".
std::string uno_pin_label(int number);

/// The name a sketch gives the pin: 0..13 as "13", 14..19 as "A0".."A5".
std::string sketch_pin_name(int number);

/// Name of the OC unit, "OC1B".
std::string oc_name(const OcChannel& oc);

}  // namespace ddmr::hil
