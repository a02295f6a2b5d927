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

namespace {
/// sin(a) / a and cos(a) for |a| <= kSmallAngle by their series, with the
/// first omitted term below 5e-18 (relative; a double rounds at 1.1e-16):
/// up to a^6 when |a| <= 1e-2,
/// up to a^2 when |a| <= 1e-4 (a straight run: the usual case). No division.
constexpr double kSmallAngle = 1e-2;
void small_sinc_cos(double a, double& sinc, double& cos) {
    constexpr double k2 = 1.0 / 2.0, k6 = 1.0 / 6.0, k12 = 1.0 / 12.0, k20 = 1.0 / 20.0,
                     k30 = 1.0 / 30.0, k42 = 1.0 / 42.0;
    const double a2 = a * a;
    if (a2 <= 1e-8) {
        sinc = 1.0 - a2 * k6;
        cos = 1.0 - a2 * k2;
        return;
    }
    sinc = 1.0 - a2 * k6 * (1.0 - a2 * k20 * (1.0 - a2 * k42));
    cos = 1.0 - a2 * k2 * (1.0 - a2 * k12 * (1.0 - a2 * k30));
}
}  // namespace

void advance_exact_arc(const DiffDriveParams& p, Pose& pose, double right_wheel_rad,
                       double left_wheel_rad, HeadingTrig& trig) {
    // eqs. (5a), (5b) x dt, with 1/(2L) formed apart from the data (off the
    // critical path: a division's latency would hold up the whole update).
    const double inv_axle = 0.5 / p.half_axle_m;
    const double vr = p.wheel_radius_right_m * right_wheel_rad;
    const double vl = p.wheel_radius_left_m * left_wheel_rad;
    const BodyVelocity d{0.5 * (vr + vl), (vr - vl) * inv_axle};
    const double half = 0.5 * d.omega_rad_s;
    if (std::abs(half) > kSmallAngle) {
        advance_exact_arc(p, pose, right_wheel_rad, left_wheel_rad);
        trig.theta_rad = std::numeric_limits<double>::quiet_NaN();
        return;
    }
    if (!(trig.theta_rad == pose.theta_rad) || trig.steps_since_exact >= HeadingTrig::kExactEvery) {
        trig.cos = std::cos(pose.theta_rad);
        trig.sin = std::sin(pose.theta_rad);
        trig.steps_since_exact = 0;
    }
    double chord_factor = 1.0;  // sin(half) / half
    double ch = 1.0;
    small_sinc_cos(half, chord_factor, ch);
    const double sh = half * chord_factor;
    // Chord = ds sin(half) / half along the mean heading theta + half.
    const double c_mid = trig.cos * ch - trig.sin * sh;
    const double s_mid = trig.sin * ch + trig.cos * sh;
    pose.x_m += d.v_m_s * chord_factor * c_mid;
    pose.y_m += d.v_m_s * chord_factor * s_mid;
    pose.theta_rad += d.omega_rad_s;
    trig.cos = c_mid * ch - s_mid * sh;
    trig.sin = s_mid * ch + c_mid * sh;
    trig.theta_rad = pose.theta_rad;
    ++trig.steps_since_exact;
}

}  // namespace ddmr::plant
