#pragma once
// The part types that sit on a wheel: a motor driver (its inputs by role) and
// an encoder (its output signals). They are part types like any other
// (their board-file keys, descriptions and datasheets come from the
// registry), wired either in the board file's `wheels:` shorthand or as a
// `parts:` entry with `wheel: right|left`. Their run-time behaviour is
// shared: MotorDriverReader reads every driver through the plant's truth
// table of its type (plant/motor_driver.hpp), EncoderInjector drives every
// encoder's pins from the plant's edges.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "plant/motor_driver.hpp"

namespace ddmr::hil {

/// A motor driver input, named as printed on the modules.
enum class DriverRole : uint8_t { pwm, dir, en, in1, in2, stby, sleep };
inline constexpr std::size_t kDriverRoleCount = 7;
/// The board-file key: "PWM", "DIR", "EN", "IN1", "IN2", "STBY", "SLEEP".
const char* role_key(DriverRole r);

/// none: the wheel has no encoder (many kit robots): the plant still turns, no pin is driven.
enum class EncoderKind : uint8_t { none, single, quadrature };

/// What a driver type has, per its datasheet's pin names.
struct MotorDriverSpec {
    plant::DriverType type = plant::DriverType::dir_pwm;
    std::string label;                    ///< the module as a user calls it: "L298N"
    std::vector<DriverRole> required;
    std::vector<DriverRole> optional_high;  ///< optional, `high` when left out (nSLEEP pulled up)
    std::vector<DriverRole> may_be_high;    ///< `high` allowed (a jumper or a pull-up)
    std::vector<DriverRole> pwm_only;       ///< needs a timer output (named PWM on the module)
    std::vector<DriverRole> shared;         ///< one pin for both motors of a dual module
};

/// An encoder type's output signals, in order ("OUT"; "A", "B").
struct EncoderSpec {
    EncoderKind kind = EncoderKind::single;
    std::vector<std::string> signals;
};

}  // namespace ddmr::hil
