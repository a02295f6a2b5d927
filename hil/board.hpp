#pragma once
// The robot's wiring as data: which Arduino pin feeds which input of each
// wheel's motor driver, and which pins each wheel's encoder drives. The
// parts that touch pins (MotorDriverReader, EncoderInjector, VcdRecorder)
// take it by reference; plant/ never sees a pin number.
//
// File form (docs/boards.md documents every key; `--board FILE`, or a
// scenario's `board:` key):
//   board: uno                       # uno (default), nano, pro-mini-8mhz (hil/board_description.hpp)
//   parts:                           # optional: any registered part (hil/parts/), wired to pins or parts
//     - {name: shield, type: 74hc595, DS: 8, SHCP: 4, STCP: 12, OE: 7}
//   wheels:
//     right:                         # motor 1, encoder 1 (plant sections motor1/encoder1)
//       motor:   {driver: dir-pwm, PWM: 10, DIR: 12}
//       encoder: {type: single, OUT: 2}
//     left:                          # motor 2, encoder 2
//       motor:   {driver: l298n, EN: 5, IN1: 7, IN2: 6, reversed: true}
//       encoder: {type: quadrature, A: 3, B: 12}   # optional: no key, no encoder
// Default: the thesis's robot (firmware/ddmr_tracking/board.yaml).

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "hil/board_description.hpp"
#include "hil/parts/part.hpp"
#include "hil/parts/wheel_part_spec.hpp"
#include "plant/motor_driver.hpp"

namespace ddmr::hil {

/// What one driver input is connected to.
struct InputWire {
    bool used = false;       ///< the driver type has this input
    bool tied_high = false;  ///< `high`: a jumper or pull-up to Vcc, no pin
    int pin = -1;            ///< the board's pin number when a pin drives it
    int line = 0;            ///< board-file line (0: not from a file)
    std::string part_output;  ///< "NAME.PORT": a part's output drives it (no pin), e.g. "shield.Q2"
    /// A board pin drives it (not `high`, not a part's output).
    [[nodiscard]] bool on_pin() const { return used && !tied_high && part_output.empty(); }
};

struct MotorWiring {
    plant::DriverType driver = plant::DriverType::dir_pwm;
    std::array<InputWire, kDriverRoleCount> input{};
    bool reversed = false;  ///< motor leads swapped: the bridge's forward turns the wheel backwards
    std::string key;        ///< where the board file wires it ("parts.m1"); empty: wheels.W.motor
    [[nodiscard]] const InputWire& operator[](DriverRole r) const { return input[static_cast<std::size_t>(r)]; }
    [[nodiscard]] InputWire& operator[](DriverRole r) { return input[static_cast<std::size_t>(r)]; }
};

struct EncoderWiring {
    EncoderKind kind = EncoderKind::single;
    std::array<int, 2> pin{-1, -1};  ///< [0]: OUT or A, [1]: B (quadrature)
    std::array<int, 2> line{0, 0};   ///< board-file lines
    bool reversed = false;           ///< quadrature channels swapped (B leads A going forward)
    std::string key;                 ///< where the board file wires it ("parts.enc_l"); empty: wheels.W.encoder
    [[nodiscard]] unsigned signals() const {
        return kind == EncoderKind::quadrature ? 2U : (kind == EncoderKind::single ? 1U : 0U);
    }
};

struct WheelWiring {
    MotorWiring motor;
    EncoderWiring encoder;
};

struct BoardWiring {
    BoardModel model = BoardModel::uno;
    /// [0]: the right wheel (motor 1, encoder 1), [1]: the left wheel (motor 2, encoder 2).
    std::array<WheelWiring, 2> wheel{};
    std::vector<PartEntry> parts;  ///< the `parts:` list (hil/parts/part.hpp), in file order
    std::string source = "built-in default board";  ///< the file it came from (messages)
};

/// "right" (index 0) or "left" (1).
const char* wheel_name(std::size_t m);
/// "dir-pwm", "l298n", "tb6612", "drv8833", "l293d", "l9110".
const char* driver_key(plant::DriverType t);
/// The module as a user calls it: "L298 shield", "L298N", "TB6612", "DRV8833", "L293D".
const char* driver_label(plant::DriverType t);
/// "right L298N EN": for warnings and messages.
std::string input_label(const BoardWiring& b, std::size_t m, DriverRole r);
/// "OUT", "A" or "B".
const char* encoder_signal_key(const EncoderWiring& e, unsigned signal);

/// The thesis's robot: right PWM 10 / DIR 12 / encoder 2, left PWM 11 / DIR 13 / encoder 3.
BoardWiring default_board();

/// Throws std::invalid_argument "SOURCE:LINE: key 'K': what is wrong" for a
/// pin the board lacks, the console UART's pins (0 and 1), a pin used twice (one dual module's
/// shared STBY/SLEEP excepted; several parts' inputs may share a pin, as two 74HC595s share a
/// clock), a PWM input on a pin without a timer output, an input fed by a part or port that
/// does not exist, a loop of parts feeding each other.
void validate(const BoardWiring& board);

/// Throws std::invalid_argument "SOURCE:LINE: key 'K': pin 19 carries Serial1's
/// RX; the host serial adapter is on Serial1" for a wiring pin on `usart`'s RXD
/// or TXD (the host adapter on a USART other than the console's: validate()
/// refuses the console's pins).
void check_host_serial_pins(const BoardWiring& board, const UsartDesc& usart);

/// Reads a board file. Throws std::runtime_error "FILE:LINE: key 'K': what
/// is wrong" for malformed YAML, an unknown or missing key, an unknown driver
/// or encoder type, a bad pin, or an invalid wiring (validate()).
BoardWiring load_board_file(const std::filesystem::path& path);

/// Every pin the wiring drives or reads, for the parts that watch them.
std::vector<int> wired_pins(const BoardWiring& board);
/// The same pins, each with the board-file key that wires it
/// ("wheels.right.encoder.OUT", "parts.sonar.ECHO"; a shared pin: its first).
std::map<int, std::string> pin_uses(const BoardWiring& board);

}  // namespace ddmr::hil
