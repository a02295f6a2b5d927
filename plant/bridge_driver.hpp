#pragma once
// One H-bridge's electrical model, for any driver chip: the terminal
// condition it puts on its motor, given the bridge state (switched model) or
// the fractions of a PWM period spent driving and braking (averaged model).
// Which inputs give which state is the chip's truth table (motor_driver.hpp).
//
//   averaged : the thesis's assumption (ch. 5): the terminals see the mean
//              V = D (V_b - drop) sgn over a period, D = the net fraction of
//              the period driven, sgn = +1 forward, -1 reverse; the rest of
//              the period counts as 0 V (a short), as in the thesis.
//   switched : the bridge state at every instant (bridge_state.hpp):
//     forward, reverse : V = +-(V_b - drop) through the two conducting
//                        switches, R_on in series, whatever the current does;
//     brake            : the winding shorted through two switches (R_brake in
//                        series); V = 0 and the supply sees nothing;
//     coast            : all four switches off; a current still flowing
//                        returns to the supply through two flyback diodes
//                        (terminals clamped at -sgn(I)(V_b + 2 V_f)) and, once
//                        it reaches zero, stays zero: discontinuous conduction.
//                        The thesis (ch. 5) names this model as missing.
// A bipolar bridge (L298, L293D) is a constant drop (its saturation voltages); a
// MOSFET bridge (TB6612FNG, DRV8833) is a resistance. Each chip's values and
// sources: default_bridge_params() below and plant/params/default.yaml.
//
// (BridgeParams, mode, BridgeInput, V_source) => MotorTerminal (dc_motor.hpp)

#include <algorithm>
#include <array>

#include "plant/bridge_state.hpp"
#include "plant/dc_motor.hpp"
#include "plant/motor_driver.hpp"
#include "plant/param_spec.hpp"

namespace ddmr::plant {

enum class DriveMode { averaged, switched };

/// Electrical parameters of one bridge (both bridges of a chip share them).
struct BridgeParams {
    /// Constant drop of the two conducting switches while driving [V], [0, 5]:
    /// the source + sink saturation voltages of a bipolar bridge (L298, L293D).
    double drop_V = 0.0;
    /// Upper + lower switch resistance while driving [ohm], [0, 10]: a MOSFET
    /// bridge's R_DS(on), in series with the armature.
    double on_resistance_ohm = 0.0;
    /// Resistance of the two switches that short the winding while braking
    /// [ohm], [0, 10].
    double brake_resistance_ohm = 0.0;
    /// Forward drop of one flyback (or body) diode while coasting [V], [0, 3].
    double flyback_diode_drop_V = 0.0;
};

const std::array<Field<BridgeParams>, 4>& bridge_fields();
void validate(const BridgeParams& p, const char* prefix);

/// Each chip's typical values (the defaults in default.yaml):
///   L298 (ST, bipolar)  : drop 1.4 V (total VCEsat 1.80 V min ... 3.2 V max at
///                         1 A, p. 3; lower at these motors' 0.1-0.3 A: our
///                         estimate), no resistance; braking through two
///                         saturated transistors is taken as a shorted winding
///                         (0 ohm); diode 0.8 V (external fast diodes, Figure 6:
///                         our estimate at ~0.2 A).
///   TB6612FNG (Toshiba) : on 0.5 ohm (Vsat(U+L) 0.5 V typ at 1 A, p. 5);
///                         brake 0.5 ohm (two low sides; derived: half of
///                         upper + lower each, so 2 x 0.25); diode 1.0 V
///                         (regenerative diode VF typ at 1 A, p. 5).
///   DRV8833 (TI)        : on 0.36 ohm (HS 200 + LS 160 mohm typ, §6.5); brake
///                         0.32 ohm (2 x LS 160 mohm: both low sides on, slow
///                         decay); diode 0.8 V (our estimate: the datasheet
///                         gives no body-diode VF).
///   L293D (TI SLRS008, Darlington): electrical characteristics, VCC1 = 5 V,
///                         VCC2 = 24 V, 25 C, L293D rows: drop 2.6 V = VOH
///                         drop 1.4 V typ (VCC2 - 1.4 V at IOH = -0.6 A) + VOL
///                         1.2 V typ (IOL = 0.6 A); worst case 1.8 + 1.8 =
///                         3.6 V. No resistance. Brake ("fast motor stop",
///                         Figure 5: both outputs on one rail) taken, as the
///                         L298's, as a shorted winding (0 ohm); derived: the
///                         real path is one switch plus one clamp diode
///                         (bipolar switches conduct one way). Diode 1.3 V:
///                         the built-in clamps, VOKH = VCC2 + 1.3 V and VOKL
///                         = 1.3 V typ at IOK = -+0.6 A.
///   L9110 (bipolar; no IC datasheet found, SENSORS.md 7): drop 1.4 V, the
///                         modules' test table quoted for the IC (outputs
///                         7.5-7.7 V from 9 V at 750 mA: 1.3-1.5 V total; an
///                         estimate at these motors' lower currents, as the
///                         L298's); no resistance; both inputs equal short the
///                         winding (0 ohm); diode 0.8 V (built-in clamps, VF
///                         not given: our estimate).
constexpr BridgeParams default_bridge_params(DriverChip chip) {
    switch (chip) {
        case DriverChip::l298: return {1.4, 0.0, 0.0, 0.8};
        case DriverChip::tb6612: return {0.0, 0.5, 0.5, 1.0};
        case DriverChip::drv8833: return {0.0, 0.36, 0.32, 0.8};
        case DriverChip::l293d: return {2.6, 0.0, 0.0, 1.3};
        case DriverChip::l9110: return {1.4, 0.0, 0.0, 0.8};
    }
    return {};
}

/// The plant file's section holding a chip's BridgeParams (params_yaml.hpp;
/// the L298's is `driver`, from when it was the only chip).
constexpr const char* params_section(DriverChip chip) {
    switch (chip) {
        case DriverChip::l298: return "driver";
        case DriverChip::tb6612: return "tb6612";
        case DriverChip::drv8833: return "drv8833";
        case DriverChip::l293d: return "l293d";
        case DriverChip::l9110: return "l9110";
    }
    return "driver";
}

/// What the plant needs of one bridge's inputs.
struct BridgeInput {
    BridgeState state = BridgeState::coast;  ///< switched mode: what the bridge does now
    double duty = 0.0;    ///< averaged mode: net fraction of the period driven, [0, 1]; also logged
    bool forward = true;  ///< averaged mode: direction of that drive; also logged
    /// Averaged mode: fraction of the period braking, [0, 1]. Adds
    /// brake_resistance in proportion to the series resistance; 0 for the
    /// thesis robot (its shield never brakes).
    double brake = 0.0;
};

/// The averaged-mode input for a bridge that spends the fractions `a` of each
/// period in each state (average_bridge): net drive D = |forward - reverse|
/// in the direction of the larger, brake = a.brake; coast counts as 0 V
/// (the averaged model's short). When forward and reverse both occur (a
/// switching direction input) the on-resistance is weighted by the net D,
/// not by forward + reverse: an approximation for that rare case.
inline BridgeInput averaged_input(const BridgeAverage& a) {
    BridgeInput in;
    in.forward = a.forward >= a.reverse;
    in.duty = in.forward ? a.forward - a.reverse : a.reverse - a.forward;
    in.brake = a.brake;
    return in;
}

/// The terminal condition the bridge imposes on its motor, for a battery
/// modelled as a source `source_V` behind `battery_resistance_ohm`
/// (eq. 19: source = V_0 - k AH - R_b x the OTHER bridge's current). This
/// bridge's own share of the R_b drop goes into series_resistance_ohm, with
/// the bridge's own on- or brake resistance.
/// With battery_resistance_ohm = 0, source_V is simply the battery voltage.
/// Inline: it runs twice per plant step.
inline MotorTerminal terminal(const BridgeParams& p, DriveMode mode, const BridgeInput& in,
                              double source_V, double battery_resistance_ohm = 0.0) {
    // Terminal voltage f (V_b - drop) - |f| R_on I with V_b = source - R_b f I:
    //   = f (source - drop) - (f^2 R_b + |f| R_on) I, f = supply factor.
    // Braking: -R_brake I. Bridge off: -sgn(I)(V_b + 2 V_f) with
    // V_b = source + R_b |I|:  = -sgn(I)(source + 2 V_f) - R_b I.
    MotorTerminal t;
    // The bridge cannot reverse the supply: below the drop it passes nothing.
    const double available_V = std::max(source_V - p.drop_V, 0.0);
    if (mode == DriveMode::averaged) {
        const double sign = in.forward ? 1.0 : -1.0;
        t.kind = MotorTerminal::Kind::driven;
        t.voltage_V = sign * in.duty * available_V;
        // Chopper average: the battery supplies the motor current duty of the time.
        t.supply_factor = sign * in.duty;
        // The switches' resistances count for the fractions they conduct.
        // With both at 0 the sum is exactly the thesis's D^2 R_b (x + 0 == x).
        t.series_resistance_ohm = in.duty * in.duty * battery_resistance_ohm +
                                  in.duty * p.on_resistance_ohm + in.brake * p.brake_resistance_ohm;
        return t;
    }
    switch (in.state) {
        case BridgeState::forward:
        case BridgeState::reverse: {
            const double sign = in.state == BridgeState::forward ? 1.0 : -1.0;
            t.kind = MotorTerminal::Kind::driven;
            t.voltage_V = sign * available_V;
            t.supply_factor = sign;
            t.series_resistance_ohm = battery_resistance_ohm + p.on_resistance_ohm;
            break;
        }
        case BridgeState::brake:
            // Shorted winding: no supply current, so no share of R_b.
            t.kind = MotorTerminal::Kind::driven;
            t.voltage_V = 0.0;
            t.supply_factor = 0.0;
            t.series_resistance_ohm = p.brake_resistance_ohm;
            break;
        case BridgeState::coast:
            t.kind = MotorTerminal::Kind::open;
            t.clamp_V = source_V + 2.0 * p.flyback_diode_drop_V;
            t.series_resistance_ohm = battery_resistance_ohm;
            break;
    }
    return t;
}

}  // namespace ddmr::plant
