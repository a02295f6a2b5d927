#pragma once
// BoardDescription: an Arduino board as data: its MCU (hil/mcu.hpp), its
// crystal, its FQBN, and its pin numbering (the Arduino core's variant:
// which port bit each digital pin number is). Every part that counts time
// takes the clock from here (through AvrCore::clock_hz()); every part that
// touches a pin looks the pin up here (board_pin()). A new board is a new
// entry in board_description.cpp.
//
// Sources: the Arduino AVR core's boards.txt (build.mcu, build.f_cpu,
// build.variant) and variants/<variant>/pins_arduino.h
// (digital_pin_to_port_PGM / digital_pin_to_bit_mask_PGM, A0 = first analog).

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hil/mcu.hpp"

namespace ddmr::hil {

/// The board-file key `board:`: uno, nano, pro-mini-8mhz, mega2560.
enum class BoardModel : uint8_t { uno, nano, pro_mini_8mhz, mega2560 };

struct BoardDescription {
    BoardModel model = BoardModel::uno;
    const char* key = "";    ///< board-file key: "pro-mini-8mhz"
    const char* label = "";  ///< "Arduino Pro Mini 3.3 V (8 MHz)"
    const char* fqbn = "";   ///< arduino-builder -fqbn
    const McuDescription* mcu = nullptr;
    uint32_t clock_hz = 0;      ///< the crystal / resonator [Hz] (build.f_cpu)
    double supply_v = 5.0;      ///< VCC = AVCC [V]: the ADC's default reference
    std::vector<PortBit> pins;  ///< Arduino pin number -> port bit
    int analog0 = 0;            ///< the number of A0 (A1 = analog0 + 1, ...)
    /// Analog inputs without a port bit (the Nano's and Pro Mini's A6, A7):
    /// named in the refusal when a board file wires one.
    std::vector<const char*> analog_only;
    /// The USART of `Serial` and of the USB/serial adapter (pins 0 and 1 on these boards).
    int console_usart = 0;

    [[nodiscard]] int pin_count() const { return static_cast<int>(pins.size()); }
    [[nodiscard]] const UsartDesc& console() const { return mcu->usarts[static_cast<std::size_t>(console_usart)]; }
};

/// Everything about one of the board's digital pins.
struct PinInfo {
    int number = 0;  ///< Arduino pin number
    char port = 'D';
    int bit = 0;
    uint16_t pin_register = 0;   ///< PINx (input level)
    uint16_t ddr_register = 0;   ///< DDRx (1 = output)
    uint16_t port_register = 0;  ///< PORTx (output level, or the pull-up of an input)
    std::optional<OcChannel> oc;       ///< the OCnx unit on the pin (a PWM pin)
    std::optional<int> ext_int;        ///< n of INTn on the pin
    std::optional<int> pcint_group;    ///< PCIEn / PCIFn / PCMSKn index of the pin's PCINT
    int pcint_bit = 0;                 ///< bit in PCMSKn
};

const BoardDescription& board_description(BoardModel model);
/// Every board, in the order docs and messages list them.
const std::vector<BoardModel>& board_models();
/// "uno" -> BoardModel::uno; nullopt for an unknown key.
std::optional<BoardModel> parse_board_key(const std::string& key);
/// "uno, nano, pro-mini-8mhz or mega2560": for messages.
std::string board_key_list();

/// The Arduino number of the pin at that port bit, if the board brings it out.
std::optional<int> pin_number_of(const BoardDescription& board, PortBit at);
/// simavr's name of a USART (AVR_IOCTL_UART_GETIRQ): '0' for USART0.
char usart_irq_name(const UsartDesc& usart);
/// Arduino's name of USART n: "Serial" (0), "Serial1" (1), ...
std::string serial_port_name(int usart_index);
/// "Serial", "Serial1", ... -> the index of a USART the board's MCU has; nullopt otherwise.
std::optional<int> parse_serial_port(const BoardDescription& board, const std::string& name);
/// The board's serial ports for messages: "Serial" or "Serial, Serial1, Serial2 or Serial3".
std::string serial_port_list(const BoardDescription& board);

/// The pin's description, or nullopt when the board has no such digital pin.
std::optional<PinInfo> board_pin(const BoardDescription& board, int number);
/// "5", "D5", "A0", "14" -> pin number; nullopt if not a digital pin of the board.
std::optional<int> parse_pin_name(const BoardDescription& board, const std::string& name);
/// Silkscreen name: "D13", "A0".
std::string pin_label(const BoardDescription& board, int number);
/// The name a sketch gives the pin: "13", "A0".
std::string sketch_pin_name(const BoardDescription& board, int number);
/// The digital pins, for messages: "0..13, A0..A5".
std::string pin_range(const BoardDescription& board);
/// The pins with a timer output (analogWrite gives PWM there): "3, 5, 6, 9, 10 and 11".
std::string pwm_pin_list(const BoardDescription& board);

}  // namespace ddmr::hil
