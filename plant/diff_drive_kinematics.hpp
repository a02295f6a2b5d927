#pragma once
// Differential-drive kinematics (thesis ch. 2, eqs. 5a, 5b, 10).
//
//   eq. (5a)  v     = (r_1 phi_1 + r_2 phi_2) / 2
//   eq. (5b)  omega = (r_1 phi_1 - r_2 phi_2) / (2 L)
//   eq. (10)  x' = v cos(theta),  y' = v sin(theta),  theta' = omega
//
// phi_1: wheel of motor 1 = RIGHT wheel, phi_2: motor 2 = LEFT wheel, so the
// right wheel turning faster gives omega > 0 (counter-clockwise), as in the
// firmware (Omega = R r1 (phi1dot - phi2dot)). No slip, no lateral motion:
// the wheels track the motor speeds (the thesis's eq. 8 assumptions).
//
// Stepping: given the wheel rotations over a step, the pose moves along the
// exact circular arc they define; for tiny turns the arc's chord factor
// sin(d/2)/(d/2) is evaluated by its series (the straight-line limit).

#include <array>
#include <limits>

#include "plant/param_spec.hpp"

namespace ddmr::plant {

struct DiffDriveParams {
    double wheel_radius_right_m = 0.0322;  ///< r_1 [m], (0, 1]. Table 2 (32.2 mm).
    double wheel_radius_left_m = 0.0322;   ///< r_2 [m], (0, 1]. Table 2.
    double half_axle_m = 0.064;            ///< L, wheel to centre P [m], (0, 10]. Table 2 (64 mm).
};

const std::array<Field<DiffDriveParams>, 3>& diff_drive_fields();
void validate(const DiffDriveParams& p, const char* prefix);

struct Pose {
    double x_m = 0.0;        ///< inertial frame [m]
    double y_m = 0.0;        ///< [m]
    double theta_rad = 0.0;  ///< heading, not wrapped [rad]
};

struct BodyVelocity {
    double v_m_s = 0.0;        ///< forward speed of P [m/s]
    double omega_rad_s = 0.0;  ///< yaw rate, counter-clockwise positive [rad/s]
};

/// eqs. (5a), (5b) from the wheel speeds [rad/s].
BodyVelocity body_velocity(const DiffDriveParams& p, double right_wheel_rad_s,
                           double left_wheel_rad_s);

/// eq. (10): d(pose)/dt.
Pose pose_derivative(const DiffDriveParams& p, const Pose& pose, double right_wheel_rad_s,
                     double left_wheel_rad_s);

/// Moves `pose` along the exact arc for wheel rotations [rad] over a step.
void advance_exact_arc(const DiffDriveParams& p, Pose& pose, double right_wheel_rad,
                       double left_wheel_rad);

/// cos and sin of the heading, carried from step to step so that a step
/// rotates them by its (small) turn instead of evaluating sin and cos of the
/// whole heading. Valid while `theta_rad` equals the pose's heading bit for
/// bit (anything else, e.g. a changed pose, makes the next step recompute
/// them); recomputed exactly every kExactEvery steps, so rounding cannot
/// build up.
struct HeadingTrig {
    static constexpr int kExactEvery = 1024;
    double theta_rad = std::numeric_limits<double>::quiet_NaN();  ///< heading they belong to
    double cos = 1.0;
    double sin = 0.0;
    int steps_since_exact = 0;
};

/// advance_exact_arc() with the heading's cos and sin carried in `trig`.
void advance_exact_arc(const DiffDriveParams& p, Pose& pose, double right_wheel_rad,
                       double left_wheel_rad, HeadingTrig& trig);

}  // namespace ddmr::plant
