#pragma once
// L298 dual full bridge (the motor shield on the Uno), one bridge per motor.
//
// Inputs per bridge: the enable pin (driven by the PWM pin) and the direction
// pin. Two models of the enable pin:
//   averaged : the thesis's assumption (ch. 5): the terminals see the mean
//              V = duty x (V_batt - drop) x sgn, with sgn = +1 forward, -1 reverse.
//   switched : the pin level at every instant. Enabled: V = sgn (V_batt - drop)
//              whatever the current does. Disabled: all four switches off; a
//              current still flowing returns to the battery through two flyback
//              diodes (terminals clamped at -sgn(I)(V_batt + 2 V_f)) and, once it
//              reaches zero, stays zero: discontinuous conduction. The thesis
//              (ch. 5) names this model as missing.
// `drop_V` lumps the source + sink saturation voltages of the bridge's two
// conducting transistors; see default.yaml for the value and its source.
//
// (params, mode, BridgeInput, V_batt) => MotorTerminal (for DcMotor).

#include <array>

#include "plant/dc_motor.hpp"
#include "plant/param_spec.hpp"

namespace ddmr::plant {

enum class DriveMode { averaged, switched };

struct L298Params {
    double drop_V = 1.4;                ///< bridge saturation drop, source + sink [V], [0, 5]. Own estimate from the ST datasheet.
    double flyback_diode_drop_V = 0.8;  ///< forward drop of one flyback diode [V], [0, 3]. Own estimate.
};

const std::array<Field<L298Params>, 2>& l298_fields();
void validate(const L298Params& p, const char* prefix);

/// The pins of one bridge as the firmware drives them.
struct BridgeInput {
    bool enable = false;  ///< switched mode: enable (PWM) pin level
    double duty = 0.0;    ///< averaged mode: PWM duty, [0, 1]
    bool forward = true;  ///< direction pin level: true = positive voltage on the motor
};

/// The terminal condition the bridge imposes on its motor, for a battery
/// modelled as a source `source_V` behind `battery_resistance_ohm`
/// (eq. 19: source = V_0 - k AH - R_b x the OTHER bridge's current). This
/// bridge's own share of the R_b drop goes into series_resistance_ohm.
/// With battery_resistance_ohm = 0, source_V is simply the battery voltage.
MotorTerminal terminal(const L298Params& p, DriveMode mode, const BridgeInput& in,
                       double source_V, double battery_resistance_ohm = 0.0);

}  // namespace ddmr::plant
