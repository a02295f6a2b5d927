#pragma once
// The goal the robot tracks (thesis ch. 4: G = [x_g, y_g, theta_g]), one case
// per CaseSpec, as a function of the controller's clock t.
//
//   circle    x_g = R cos(w t), y_g = R sin(w t), theta_g = theta_0 + w t.
//             The firmware's cases are circles about the origin, where the
//             robot starts (heading 0), so the goal starts R ahead on the x
//             axis heading +y: case 1 R = 0.6 m, w = 0.5236 rad/s; case 2
//             R = 0.4 m, w = 0.7854 rad/s; theta_0 = 1.571 (the sketch's
//             `Angref`, advanced by dt*w per iteration). A custom circle
//             (circle_case) uses w = 2 pi / T and theta_0 = pi / 2 exactly.
//   line_step the thesis's appendix A2 step test: the goal moves along the x
//             axis from the origin at `line_speed_m_s` heading 0 (the robot
//             starts on it, error zero); at t = step_time_s (10 s) it jumps
//             by step_m (0.2 m, "the 20 cm step") along x (ahead: a step in the
//             robot frame's X error) or y (sideways: a step in Y) and goes on
//             at the same speed. theta_g = 0 throughout.
//
// goal_position is templated so the float32 switch can evaluate it as the
// robot does (`0.6*cos(0.5236*t)` in float).

#include <cmath>
#include <string>

namespace ddmr::hostsim {

enum class CaseKind { circle, line_step };
enum class StepAxis { x, y };

struct CaseSpec {
    std::string name = "case1";   ///< "case1", "case2", "circle", "line-x", "line-y"
    CaseKind kind = CaseKind::circle;
    // --- circle
    double radius_m = 0.6;        ///< R [m], > 0
    double rate_rad_s = 0.5236;   ///< w [rad/s], > 0: the goal's turn rate (0 for a line)
    double heading0_rad = 1.571;  ///< theta_g at t = 0 [rad]
    // --- line_step
    double line_speed_m_s = 0.5;  ///< v_g along x [m/s], >= 0
    double step_m = 0.2;          ///< size of the step [m]
    double step_time_s = 10.0;    ///< when it happens, on the controller's clock [s]
    StepAxis step_axis = StepAxis::x;
    // --- both
    double duration_s = 12.0;     ///< run length on the controller's clock [s] (NUM x dt)
    /// The sketch writes the EEPROM log in this case (case 1 and the custom
    /// cases: yes; case 2's loop writes none).
    bool logs_eeprom = true;
};

/// The sketch's case 1 or 2. Throws std::invalid_argument for another number.
CaseSpec firmware_case(int case_number);
/// A circle of radius R about the origin, one lap in T seconds (w = 2 pi / T,
/// theta_0 = pi / 2, duration T). Throws std::invalid_argument unless R, T > 0.
CaseSpec circle_case(double radius_m, double period_s);
/// Appendix A2's straight line at 0.5 m/s with a 20 cm step at 10 s; 20 s long.
CaseSpec line_step_case(StepAxis axis);

/// Throws std::invalid_argument naming the field and value.
void validate(const CaseSpec& c);

template <class Real>
struct GoalPoint {
    Real x_m;
    Real y_m;
};

/// (x_g, y_g) at controller time t, evaluated in Real.
template <class Real>
GoalPoint<Real> goal_position(const CaseSpec& c, Real t_s) {
    if (c.kind == CaseKind::circle) {
        const Real r = static_cast<Real>(c.radius_m);
        const Real w = static_cast<Real>(c.rate_rad_s);
        return {r * std::cos(w * t_s), r * std::sin(w * t_s)};
    }
    const Real along = static_cast<Real>(c.line_speed_m_s) * t_s;
    const Real step = t_s >= static_cast<Real>(c.step_time_s) ? static_cast<Real>(c.step_m) : Real(0);
    if (c.step_axis == StepAxis::x) return {along + step, Real(0)};
    return {along, step};
}

/// theta_g at controller time t [rad], the continuous form of `Angref`.
inline double goal_heading_rad(const CaseSpec& c, double t_s) {
    return c.kind == CaseKind::circle ? c.heading0_rad + c.rate_rad_s * t_s : c.heading0_rad;
}

/// The goal's own velocity (v_g, w_g): the feed-forward that makes eq. (16)
/// hold. For the firmware's cases the sketch's vref = wref = 0.2 differ
/// from these (R w = 0.314 m/s, w = 0.524 rad/s for case 1).
struct GoalVelocity {
    double v_m_s = 0.0;
    double omega_rad_s = 0.0;
};
GoalVelocity goal_velocity(const CaseSpec& c);

}  // namespace ddmr::hostsim
