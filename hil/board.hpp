#pragma once
// The Uno board as data: which Arduino pin is wired to which input of the
// L298 shield and which Hall sensor drives which pin. One definition, used by
// the driver reader and the encoder injector; another wiring is a YAML file,
// not a code change.
//
// Default (the thesis's robot, ddmr_tracking.ino):
//   motor 1 (right wheel): enable pin 10 (OC1B), direction pin 12
//   motor 2 (left wheel) : enable pin 11 (OC2A), direction pin 13
//   encoder 1 (motor 1)  : pin 2 (INT0)
//   encoder 2 (motor 2)  : pin 3 (INT1)
//
// YAML form (a `board:` section, in a --board file or in the --plant file):
//   board:
//     motor1:   {enable_pin: 10, direction_pin: 12}
//     motor2:   {enable_pin: 11, direction_pin: 13}
//     encoder1: {pin: 2}
//     encoder2: {pin: 3}

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace ddmr::hil {

/// Where an Arduino Uno digital pin (0..19; 14..19 = A0..A5) sits on the chip.
struct PinLocation {
    char port = 'D';    ///< 'B', 'C' or 'D'
    int bit = 0;        ///< 0..7
    uint16_t port_register = 0;  ///< PORTx data-space address (output level)
};

/// The Uno pin's port and bit, or nullopt if the Uno has no such pin.
std::optional<PinLocation> uno_pin_location(int pin);

/// A timer output-compare channel in 8-bit phase-correct PWM, as the Arduino
/// core's init() configures Timer1 and Timer2 (prescaler 64).
struct PwmChannel {
    const char* name = "";         ///< "OC1B", ...
    int timer = 1;                 ///< 1 or 2
    uint16_t tccra = 0;            ///< TCCRnA (COM bits)
    uint8_t com1_mask = 0;         ///< COMnx1: non-inverting output on the pin
    uint16_t tccrb = 0;            ///< TCCRnB (clock select: starts the counter)
    uint16_t ocr_low = 0;          ///< OCRnx (low byte)
    uint16_t ocr_high = 0;         ///< OCRnxH for Timer1's 16-bit registers, else 0
};

/// The phase-correct PWM channel on this Uno pin (9, 10: Timer1; 3, 11:
/// Timer2), or nullopt. Pins 5 and 6 (Timer0) run fast PWM, not modelled.
std::optional<PwmChannel> uno_pwm_channel(int pin);

/// External interrupt on this Uno pin: 0 for pin 2 (INT0), 1 for pin 3 (INT1).
std::optional<int> uno_external_interrupt(int pin);

struct MotorWiring {
    int enable_pin = 10;     ///< L298 ENx: a phase-correct PWM pin
    int direction_pin = 12;  ///< L298 INx: high = forward
};

struct EncoderWiring {
    int pin = 2;  ///< the Hall sensor's output
};

struct BoardWiring {
    std::array<MotorWiring, 2> motor{};      ///< [0]: motor 1 (right), [1]: motor 2 (left)
    std::array<EncoderWiring, 2> encoder{};  ///< [0]: encoder of motor 1, [1]: of motor 2
};

/// The thesis's robot.
BoardWiring uno_default_board();

/// Throws std::invalid_argument naming `source`, the key and the pin when a
/// pin does not exist on the Uno, an enable pin is not a phase-correct PWM
/// pin, or two functions share a pin.
void validate(const BoardWiring& board, const std::string& source);

/// The `board:` section of a YAML file over the defaults; nullopt when the file
/// has none. Throws std::runtime_error with file:line, key and value for a
/// malformed file, an unknown key, a non-integer pin or an invalid wiring.
std::optional<BoardWiring> load_board_section(const std::filesystem::path& path);

}  // namespace ddmr::hil
