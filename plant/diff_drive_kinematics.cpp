#include "plant/diff_drive_kinematics.hpp"

#include <cmath>

namespace ddmr::plant {

const std::array<Field<DiffDriveParams>, 3>& diff_drive_fields() {
    using P = DiffDriveParams;
    static const std::array<Field<P>, 3> table{{
        {"wheel_radius_right_m", "m", positive(1.0), &P::wheel_radius_right_m},
        {"wheel_radius_left_m", "m", positive(1.0), &P::wheel_radius_left_m},
        {"half_axle_m", "m", positive(10.0), &P::half_axle_m},
    }};
    return table;
}

void validate(const DiffDriveParams& p, const char* prefix) {
    validate_fields(p, diff_drive_fields(), prefix);
}

BodyVelocity body_velocity(const DiffDriveParams& p, double right_wheel_rad_s,
                           double left_wheel_rad_s) {
    const double vr = p.wheel_radius_right_m * right_wheel_rad_s;
    const double vl = p.wheel_radius_left_m * left_wheel_rad_s;
    return BodyVelocity{0.5 * (vr + vl), (vr - vl) / (2.0 * p.half_axle_m)};
}

Pose pose_derivative(const DiffDriveParams& p, const Pose& pose, double right_wheel_rad_s,
                     double left_wheel_rad_s) {
    const BodyVelocity b = body_velocity(p, right_wheel_rad_s, left_wheel_rad_s);
    return Pose{b.v_m_s * std::cos(pose.theta_rad), b.v_m_s * std::sin(pose.theta_rad),
                b.omega_rad_s};
}

void advance_exact_arc(const DiffDriveParams& p, Pose& pose, double right_wheel_rad,
                       double left_wheel_rad) {
    // Distance along the arc and turn over the step, eqs. (5a), (5b) x dt.
    const BodyVelocity d = body_velocity(p, right_wheel_rad, left_wheel_rad);
    const double ds = d.v_m_s;
    const double dtheta = d.omega_rad_s;
    // Chord = ds sin(dtheta/2) / (dtheta/2), along the mean heading.
    const double half = 0.5 * dtheta;
    const double chord_factor =
        std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : std::sin(half) / half;
    const double heading = pose.theta_rad + half;
    pose.x_m += ds * chord_factor * std::cos(heading);
    pose.y_m += ds * chord_factor * std::sin(heading);
    pose.theta_rad += dtheta;
}

}  // namespace ddmr::plant
