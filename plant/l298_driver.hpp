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

#include <algorithm>
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
/// Inline: it runs twice per plant step.
inline MotorTerminal terminal(const L298Params& p, DriveMode mode, const BridgeInput& in,
                              double source_V, double battery_resistance_ohm = 0.0) {
    // Terminal voltage f (V_b - drop) with V_b = source - R_b f I:
    //   = f (source - drop) - f^2 R_b I, f = supply factor.
    // Bridge off: -sgn(I)(V_b + 2 V_f) with V_b = source + R_b |I|:
    //   = -sgn(I)(source + 2 V_f) - R_b I.
    MotorTerminal t;
    const double sign = in.forward ? 1.0 : -1.0;
    // The bridge cannot reverse the supply: below the drop it passes nothing.
    const double available_V = std::max(source_V - p.drop_V, 0.0);
    if (mode == DriveMode::averaged) {
        t.kind = MotorTerminal::Kind::driven;
        t.voltage_V = sign * in.duty * available_V;
        // Chopper average: the battery supplies the motor current duty of the time.
        t.supply_factor = sign * in.duty;
        t.series_resistance_ohm = in.duty * in.duty * battery_resistance_ohm;
    } else if (in.enable) {
        t.kind = MotorTerminal::Kind::driven;
        t.voltage_V = sign * available_V;
        t.supply_factor = sign;
        t.series_resistance_ohm = battery_resistance_ohm;
    } else {
        t.kind = MotorTerminal::Kind::open;
        t.clamp_V = source_V + 2.0 * p.flyback_diode_drop_V;
        t.series_resistance_ohm = battery_resistance_ohm;
    }
    return t;
}

}  // namespace ddmr::plant
