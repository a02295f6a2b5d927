#include "plant/dc_motor.hpp"

#include <cmath>

namespace ddmr::plant {

const std::array<Field<DcMotorParams>, 8>& dc_motor_fields() {
    using P = DcMotorParams;
    static const std::array<Field<P>, 8> table{{
        {"resistance_ohm", "ohm", positive(1000.0), &P::resistance_ohm},
        {"inductance_H", "H", positive(10.0), &P::inductance_H},
        {"back_emf_V_s_per_rad", "V s/rad", positive(10.0), &P::back_emf_V_s_per_rad},
        {"torque_N_m_per_A", "N m/A", positive(10.0), &P::torque_N_m_per_A},
        {"inertia_kg_m2", "kg m^2", positive(1.0), &P::inertia_kg_m2},
        {"viscous_friction_N_m_s_per_rad", "N m s/rad", positive(1.0),
         &P::viscous_friction_N_m_s_per_rad},
        {"coulomb_friction_N_m", "N m", non_negative(1.0), &P::coulomb_friction_N_m},
        {"gear_ratio", "1", positive(10000.0), &P::gear_ratio},
    }};
    return table;
}

void validate(const DcMotorParams& p, const char* prefix) {
    validate_fields(p, dc_motor_fields(), prefix);
}

namespace {
double sgn(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }
}  // namespace

DcMotorDerivative derivative(const DcMotorParams& p, const DcMotorState& x,
                             const MotorTerminal& u) {
    DcMotorDerivative d;
    const double i = x.current_A;
    const double w = x.speed_rad_s;
    const double r = p.resistance_ohm + u.series_resistance_ohm;
    // Electrical side, eq. (9b): L_a dI/dt = V - R_a I - K_a w.
    if (u.kind == MotorTerminal::Kind::driven) {
        d.current_A_s = (u.voltage_V - r * i - p.back_emf_V_s_per_rad * w) / p.inductance_H;
    } else if (i != 0.0) {
        // Bridge off: the flyback diodes clamp the terminals at -sgn(I) clamp_V.
        const double v = -sgn(i) * u.clamp_V;
        d.current_A_s = (v - r * i - p.back_emf_V_s_per_rad * w) / p.inductance_H;
    }  // open and I == 0: open circuit, I stays 0.

    // Mechanical side, eq. (9a) + Coulomb friction with stiction.
    const double torque = p.torque_N_m_per_A * i;
    if (w != 0.0) {
        d.speed_rad_s2 = (torque - p.viscous_friction_N_m_s_per_rad * w -
                          p.coulomb_friction_N_m * sgn(w)) /
                         p.inertia_kg_m2;
    } else if (std::abs(torque) > p.coulomb_friction_N_m) {
        d.speed_rad_s2 = (torque - p.coulomb_friction_N_m * sgn(torque)) / p.inertia_kg_m2;
    }  // stuck: |K_t I| <= T_c holds the shaft.
    d.angle_rad_s = w;
    return d;
}

double steady_state_speed_rad_s(const DcMotorParams& p, double voltage_V) {
    const double num = p.torque_N_m_per_A * voltage_V - p.resistance_ohm * p.coulomb_friction_N_m;
    const double den = p.resistance_ohm * p.viscous_friction_N_m_s_per_rad +
                       p.torque_N_m_per_A * p.back_emf_V_s_per_rad;
    return num > 0.0 ? num / den : 0.0;
}

}  // namespace ddmr::plant
