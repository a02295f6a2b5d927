#include "plant/motor_driver.hpp"

#include <array>
#include <cstddef>

namespace ddmr::plant {

namespace {

// One table for two chips: an enable and two half-bridge inputs.
// ST L298, Figure 6 "Bidirectional DC Motor Control" (p. 6; C, D = IN1, IN2):
//   EN L             free running motor stop (all four transistors off) -> coast
//   EN H, C H, D L   forward                                           -> forward
//   EN H, C L, D H   reverse                                           -> reverse
//   EN H, C = D      fast motor stop (both upper or both lower on)     -> brake
// TI L293D (SLRS008), Figure 5 "Bidirectional DC motor control" (1A, 2A = IN1,
// IN2), the same rows: EN H, 1A H, 2A L "turn left" -> forward (IN1 H, as the
// L298's); 1A L, 2A H "turn right" -> reverse; 1A = 2A "fast motor stop" ->
// brake. EN L is printed "fast motor stop" too, but Figure 4 calls it
// "free-running motor stop" and the function table makes the outputs Z
// (EN = L: Y = Z) -> coast, through the built-in clamp diodes.
BridgeState enable_in1_in2(bool en, bool in1, bool in2) {
    if (!en) return BridgeState::coast;
    if (in1 == in2) return BridgeState::brake;
    return in1 ? BridgeState::forward : BridgeState::reverse;
}

// The thesis's shield: the PWM pin drives the L298's EN, one DIR pin sets the
// direction (the two inputs opposite), so it never brakes:
//   PWM L        coast (EN low, Figure 6 "free running motor stop")
//   PWM H, DIR H forward
//   PWM H, DIR L reverse
BridgeState dir_pwm(bool pwm, bool dir) {
    if (!pwm) return BridgeState::coast;
    return dir ? BridgeState::forward : BridgeState::reverse;
}

// Toshiba TB6612FNG, "H-SW Control Function" (p. 4):
//   STBY L                  standby, OUT1 = OUT2 = OFF (high-Z)   -> coast
//   IN1 H, IN2 H, PWM H/L   short brake                           -> brake
//   IN1 L, IN2 H, PWM H     CCW, OUT1 L, OUT2 H                   -> reverse
//   IN1 L, IN2 H, PWM L     short brake                           -> brake
//   IN1 H, IN2 L, PWM H     CW, OUT1 H, OUT2 L                    -> forward
//   IN1 H, IN2 L, PWM L     short brake                           -> brake
//   IN1 L, IN2 L, PWM H     stop, OUT1 = OUT2 = OFF (high-Z)      -> coast
//   IN1 L, IN2 L, PWM L     NOT in the table. Taken as stop (coast), like
//                           the row above: with both inputs low neither
//                           output is told to drive (our assumption).
BridgeState tb6612(bool stby, bool in1, bool in2, bool pwm) {
    if (!stby) return BridgeState::coast;
    if (in1 && in2) return BridgeState::brake;
    if (!in1 && !in2) return BridgeState::coast;
    if (!pwm) return BridgeState::brake;
    return in1 ? BridgeState::forward : BridgeState::reverse;
}

// TI DRV8833 (SLVSAR1E), §7.3.2 Table 1 "H-Bridge Logic"; nSLEEP low puts the
// bridges in Hi-Z and ignores the inputs (§7.3.4, §7.4 Table 4):
//   nSLEEP 0          sleep, Hi-Z                  -> coast
//   xIN1 0, xIN2 0    Z, Z: coast / fast decay     -> coast
//   xIN1 0, xIN2 1    L, H: reverse                -> reverse
//   xIN1 1, xIN2 0    H, L: forward                -> forward
//   xIN1 1, xIN2 1    L, L: brake / slow decay     -> brake
BridgeState drv8833(bool sleep, bool in1, bool in2) {
    if (!sleep) return BridgeState::coast;
    if (in1 && in2) return BridgeState::brake;
    if (in1) return BridgeState::forward;
    return in2 ? BridgeState::reverse : BridgeState::coast;
}

// L9110 / L9110S (HG7881 modules): no readable datasheet of the IC was found;
// the modules' vendors give (../shared/SENSORS.md section 7: Banana Robotics,
// SunFounder):
//   IA H, IB L   OA H, OB L: forward   -> forward
//   IA L, IB H   OA L, OB H: reverse   -> reverse
//   IA L, IB L   OA L, OB L: off       -> brake
//   IA H, IB H   OA H, OB H: off       -> brake
// Both "off" rows drive the two outputs to one rail: the winding is shorted
// (brake, slow decay), not left open (derived from the output levels; whether
// the IC brakes or coasts there is unverified).
BridgeState l9110(bool in1, bool in2) {
    if (in1 == in2) return BridgeState::brake;
    return in1 ? BridgeState::forward : BridgeState::reverse;
}

/// One input of a driver type: where its level and its duty live.
struct Input {
    bool DriverInputLevels::*level;
    double DriverInputDuties::*duty;
};
constexpr std::size_t kMaxInputs = 4;
struct InputSet {
    std::array<Input, kMaxInputs> input;
    std::size_t count;
};

/// The inputs a driver type reads (the others do not change its state).
InputSet inputs_of(DriverType t) {
    using L = DriverInputLevels;
    using D = DriverInputDuties;
    constexpr Input pwm{&L::pwm, &D::pwm};
    constexpr Input dir{&L::dir, &D::dir};
    constexpr Input en{&L::en, &D::en};
    constexpr Input in1{&L::in1, &D::in1};
    constexpr Input in2{&L::in2, &D::in2};
    constexpr Input stby{&L::stby, &D::stby};
    constexpr Input sleep{&L::sleep, &D::sleep};
    switch (t) {
        case DriverType::dir_pwm: return {{pwm, dir}, 2};
        case DriverType::l298n:
        case DriverType::l293d: return {{en, in1, in2}, 3};
        case DriverType::tb6612: return {{pwm, in1, in2, stby}, 4};
        case DriverType::drv8833: return {{in1, in2, sleep}, 3};
        case DriverType::l9110: return {{in1, in2}, 2};
    }
    return {{}, 0};
}

}  // namespace

BridgeState bridge_state(DriverType type, const DriverInputLevels& in) {
    switch (type) {
        case DriverType::dir_pwm: return dir_pwm(in.pwm, in.dir);
        case DriverType::l298n:
        case DriverType::l293d: return enable_in1_in2(in.en, in.in1, in.in2);
        case DriverType::tb6612: return tb6612(in.stby, in.in1, in.in2, in.pwm);
        case DriverType::drv8833: return drv8833(in.sleep, in.in1, in.in2);
        case DriverType::l9110: return l9110(in.in1, in.in2);
    }
    return BridgeState::coast;
}

BridgeAverage average_bridge(DriverType type, const DriverInputDuties& duties) {
    const InputSet set = inputs_of(type);
    DriverInputLevels base;  // static inputs: duty 1 high, duty 0 (or NaN) low
    std::array<const Input*, kMaxInputs> switching{};
    std::array<double, kMaxInputs> duty{};
    std::size_t k = 0;
    for (std::size_t i = 0; i < set.count; ++i) {
        const Input& in = set.input[i];
        const double d = duties.*in.duty;
        if (d >= 1.0) {
            base.*in.level = true;
        } else if (d > 0.0) {
            switching[k] = &in;
            duty[k] = d;
            ++k;
        }
    }
    BridgeAverage avg;
    const unsigned combos = 1U << k;
    for (unsigned combo = 0; combo < combos; ++combo) {
        DriverInputLevels levels = base;
        double weight = 1.0;
        for (std::size_t j = 0; j < k; ++j) {
            const bool high = ((combo >> j) & 1U) != 0U;
            levels.*(switching[j]->level) = high;
            weight *= high ? duty[j] : 1.0 - duty[j];
        }
        switch (bridge_state(type, levels)) {
            case BridgeState::forward: avg.forward += weight; break;
            case BridgeState::reverse: avg.reverse += weight; break;
            case BridgeState::brake: avg.brake += weight; break;
            case BridgeState::coast: avg.coast += weight; break;
        }
    }
    return avg;
}

}  // namespace ddmr::plant
