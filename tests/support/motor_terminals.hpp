#pragma once
// Motor terminal conditions the plant tests drive motors with.
#include "plant/dc_motor.hpp"

namespace ddmr::test {

/// The bridge forces `v` volts across the motor; the supply carries the
/// motor's current one for one (full duty, forward).
inline plant::MotorTerminal driven(double v) {
    plant::MotorTerminal u;
    u.kind = plant::MotorTerminal::Kind::driven;
    u.voltage_V = v;
    u.supply_factor = 1.0;
    return u;
}

}  // namespace ddmr::test
