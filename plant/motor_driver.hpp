#pragma once
// Motor-driver truth tables: the logic levels on one bridge's inputs => the
// bridge state (bridge_state.hpp). The plant never sees pin numbers: the HIL
// (the board file) says which pin feeds which input and hands over levels
// (switched model) or the fraction of time each input is high (averaged
// model). Sources: /work/shared/DRIVERS.md and the datasheets it cites.
//
//   type     chip      inputs per bridge        table
//   dir_pwm  L298      PWM (= EN), DIR          the thesis's shield (Ardumoto): the
//                                               PWM pin on the enable, one direction pin
//   l298n    L298      EN, IN1, IN2             ST L298, Figure 6 (p. 6)
//   tb6612   TB6612FNG PWM, IN1, IN2, STBY      Toshiba, "H-SW Control Function" (p. 4)
//   drv8833  DRV8833   IN1, IN2, nSLEEP         TI SLVSAR1E, §7.3.2 Table 1
//   l293d    L293D     EN, IN1 (1A), IN2 (2A)   TI SLRS008, Figure 5 (the l298n
//                                               table: one function serves both)
//   l9110    L9110     IN1 (IA), IN2 (IB)       module vendors' table (SENSORS.md 7)
//
// (DriverType, input levels)  => BridgeState     (bridge_state)
// (DriverType, input duties)  => BridgeAverage   (average_bridge)

#include <cstdint>

#include "plant/bridge_state.hpp"

namespace ddmr::plant {

/// How the firmware's pins drive one bridge (a board-file choice).
enum class DriverType : std::uint8_t { dir_pwm, l298n, tb6612, drv8833, l293d, l9110 };

/// The silicon behind a driver type: it selects the electrical parameters
/// (bridge_driver.hpp). dir_pwm and l298n are both L298 chips. l293d is the
/// L293D (built-in clamp diodes), not the L293, whose diodes are external.
enum class DriverChip : std::uint8_t { l298, tb6612, drv8833, l293d, l9110 };

constexpr DriverChip chip_of(DriverType t) {
    switch (t) {
        case DriverType::dir_pwm:
        case DriverType::l298n: return DriverChip::l298;
        case DriverType::tb6612: return DriverChip::tb6612;
        case DriverType::drv8833: return DriverChip::drv8833;
        case DriverType::l293d: return DriverChip::l293d;
        case DriverType::l9110: return DriverChip::l9110;
    }
    return DriverChip::l298;
}

/// The logic level of each input a driver type has (the others are ignored).
/// `sleep` is the DRV8833's nSLEEP: high = awake.
struct DriverInputLevels {
    bool pwm = false;
    bool dir = false;
    bool en = false;
    bool in1 = false;
    bool in2 = false;
    bool stby = false;
    bool sleep = false;
};

/// The bridge state a driver type's truth table gives for `levels`.
BridgeState bridge_state(DriverType type, const DriverInputLevels& levels);

/// Averaged model: the fraction of time each input is high, [0, 1] (values
/// outside count as 0 or 1, NaN as 0).
struct DriverInputDuties {
    double pwm = 0.0;
    double dir = 0.0;
    double en = 0.0;
    double in1 = 0.0;
    double in2 = 0.0;
    double stby = 0.0;
    double sleep = 0.0;
};

/// Fractions of the period the bridge spends in each state; they sum to 1.
struct BridgeAverage {
    double forward = 0.0;
    double reverse = 0.0;
    double brake = 0.0;
    double coast = 0.0;
};

/// The time-average of bridge_state over the inputs' duties. Inputs at duty
/// 0 or 1 are static. Each input of the type with a duty strictly between 0
/// and 1 is treated as an independent two-level signal: the result sums
/// bridge_state over the 2^k level combinations of the k switching inputs,
/// each weighted by the product of the inputs' duties (high) or one minus
/// them (low). Exact when at most one input switches (one PWM pin, the
/// usual case). With two or more it assumes their levels uncorrelated,
/// which two PWM outputs of one timer are not (they share the period and
/// are aligned): then it is an approximation.
BridgeAverage average_bridge(DriverType type, const DriverInputDuties& duties);

}  // namespace ddmr::plant
