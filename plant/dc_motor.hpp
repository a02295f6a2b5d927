#pragma once
// Permanent-magnet DC gear motor (thesis ch. 3, eqs. 9a-9f), one per wheel.
//
//   eq. (9b)  L_a dI/dt = V - (R_a + R_s) I - K_a w   (R_s: supply side, see MotorTerminal)
//   eq. (9a)  J   dw/dt = K_t I - F w - T_c sgn(w)      (T_c: Coulomb term, ours)
//             dtheta/dt = w                              (shaft angle, for the encoder)
//
// w is the MOTOR SHAFT speed; the wheel turns at w / gear_ratio.
// Coulomb friction with stiction: at w = 0 the shaft stays stuck while
// |K_t I| <= T_c. The thesis (ch. 8) asks for "a better model of friction";
// viscous-only friction (its eq. 9a) is the special case T_c = 0.
//
// Signals: input  MotorTerminal (what the driver puts on the terminals)
//          state  DcMotorState (current_A, speed_rad_s, angle_rad)
//          output DcMotorDerivative, wheel speed.
// The exact piecewise solution used for stepping is in motor_segment.hpp.

#include <array>
#include <cstdint>

#include "plant/param_spec.hpp"
#include "plant/units.hpp"

namespace ddmr::plant {

struct DcMotorParams {
    double resistance_ohm = 5.32;          ///< R_a [ohm], (0, 1000]. Table 2 (R_a1).
    double inductance_H = 2.3e-3;          ///< L_a [H], (0, 10]. Table 2 / 10: see default.yaml.
    double back_emf_V_s_per_rad = 0.00384; ///< K_a [V s/rad] at the motor shaft, (0, 10]. Fit to 210 RPM.
    double torque_N_m_per_A = 0.00384;     ///< K_t [N m/A], (0, 10]. = K_a in SI (thesis fig. 3-1).
    double inertia_kg_m2 = 1.9e-7;         ///< J [kg m^2] at the motor shaft, rotor + reflected load, (0, 1].
    double viscous_friction_N_m_s_per_rad = 2.2e-7;  ///< F [N m s/rad], (0, 1]. Own estimate.
    double coulomb_friction_N_m = 2.3e-4;  ///< T_c [N m], [0, 1]. Own estimate.
    double gear_ratio = 48.0;              ///< GR, motor turns per wheel turn, (0, 10000]. Table 2.
};

/// Field table: keys, units and valid ranges of DcMotorParams.
const std::array<Field<DcMotorParams>, 8>& dc_motor_fields();

/// Throws std::invalid_argument naming `prefix.key`, value and range.
void validate(const DcMotorParams& p, const char* prefix);

struct DcMotorState {
    double current_A = 0.0;    ///< I_a [A]
    double speed_rad_s = 0.0;  ///< motor shaft speed w [rad/s]
    double angle_rad = 0.0;    ///< motor shaft angle [rad], integral of w
};

/// What the bridge does to the motor terminals during an interval.
struct MotorTerminal {
    enum class Kind {
        /// The bridge forces `voltage_V` across the motor whatever the
        /// current's sign (averaged model, or switched model while driving
        /// or braking: bridge_driver.hpp).
        driven,
        /// The bridge is off. Current that still flows returns to the supply
        /// through two flyback diodes, so the terminals see
        /// -sgn(I) * clamp_V until I reaches zero; then the motor is
        /// open-circuit (I = 0, it coasts).
        open,
    };
    Kind kind = Kind::driven;
    double voltage_V = 0.0;  ///< driven: terminal voltage [V]
    double clamp_V = 0.0;    ///< open: battery + 2 diode drops [V], > 0
    /// driven: battery current per motor ampere (duty x direction sign), so
    /// the supply current is supply_factor * I.
    double supply_factor = 0.0;
    /// Resistance in series with the armature from the supply side [ohm]:
    /// the battery's R_b as this motor sees it (supply_factor^2 R_b) plus
    /// the bridge's own conducting switches (on- or brake resistance). It
    /// adds to R_a in eq. (9b), so the motor's own current sags its own
    /// voltage exactly, with no lag.
    double series_resistance_ohm = 0.0;
};

struct DcMotorDerivative {
    double current_A_s = 0.0;    ///< dI/dt [A/s]
    double speed_rad_s2 = 0.0;   ///< dw/dt [rad/s^2]
    double angle_rad_s = 0.0;    ///< dtheta/dt = w [rad/s]
};

/// The model: (params, state, terminal) => d(state)/dt, eqs. (9a), (9b),
/// including stiction and the open-circuit case. Used by tests and by any
/// general-purpose integrator; the plant steps with the exact solution.
DcMotorDerivative derivative(const DcMotorParams& p, const DcMotorState& x,
                             const MotorTerminal& u);

/// Wheel speed [rad/s] for a motor shaft speed.
inline double wheel_speed_rad_s(const DcMotorParams& p, double motor_speed_rad_s) {
    return motor_speed_rad_s / p.gear_ratio;
}

/// Steady-state motor speed [rad/s] for a constant terminal voltage V > 0
/// when the shaft turns forward (viscous + Coulomb):
///   0 = K_t I - F w - T_c,  0 = V - R_a I - K_a w
///   => w = (K_t V - R_a T_c) / (R_a F + K_t K_a), clamped at 0 (stuck).
double steady_state_speed_rad_s(const DcMotorParams& p, double voltage_V);

}  // namespace ddmr::plant
