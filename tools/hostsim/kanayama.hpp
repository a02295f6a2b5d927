#pragma once
// Kanayama's tracking controller (thesis ch. 4), templated on the number type
// so the same lines run in double (ideal) or float (the AVR's 32-bit double).
//
//   eq. (12)  [x_e]   [ cos th  sin th  0] [x_g - x ]
//             [y_e] = [-sin th  cos th  0] [y_g - y ]      (robot frame)
//             [th_e]  [   0       0     1] [th_g - th]
//   eq. (14)  v = v_g cos th_e + K_x x_e
//             w = w_g + v_g (K_y y_e + K_w sin th_e)
//   eq. (15)  V = (x_e^2 + y_e^2) / 2 + (1 - cos th_e) / K_y
//   eq. (16)  dV/dt = -K_x x_e^2 - v_g K_w sin^2 th_e / K_y   (<= 0 for v_g >= 0,
//             when v_g, w_g are the goal's true velocities and the robot
//             moves at (v, w) exactly)
//
// The lines follow the sketch's order of operations, so in float they round
// as the robot does: `errxr=cos(Theta)*errx+sin(Theta)*erry;`,
// `v=vref*cos(etheta)+kx*errxr;`, `w=wref+vref*(ky*erryr+kw*sin(etheta));`.
// (The MATLAB listing of appendix A1 writes w = wref + ky y_e + kw vref sin th_e,
// without v_g on K_y; eq. (14) and the firmware have it. We follow eq. (14).)

#include <cmath>

namespace ddmr::hostsim {

/// The controller's constants. Dimensions: K_x [1/s], K_y [1/m^2] (so that
/// v_g K_y y_e is a rate), K_w [1/m]; all >= 0 (eq. 16 needs K_y > 0).
struct Gains {
    double kx = 1.1;          ///< K_x: the thesis's intended value; the sketch's `const int` makes it 1
    double ky = 6.0;          ///< K_y
    double kw = 8.0;          ///< K_w
    double vref_m_s = 0.2;    ///< v_g, the feed-forward speed (the sketch's `vref`)
    double wref_rad_s = 0.2;  ///< w_g, the feed-forward turn rate (the sketch's `wref`)
};

/// The gains as `const int kx=...;` compiles them: K_x, K_y, K_w truncated
/// toward zero (1.1 -> 1; 6 and 8 stay). v_g and w_g are floats in the
/// sketch and stay.
Gains integer_gains(const Gains& g);

/// Throws std::invalid_argument naming the gain unless all are finite,
/// K_x, K_y, K_w in [0, 1000] and |v_g| <= 10 m/s, |w_g| <= 100 rad/s.
void validate(const Gains& g);

template <class Real>
struct PoseEstimate {
    Real x_m;
    Real y_m;
    Real theta_rad;
};

/// eq. (12): the error pose in the robot frame.
template <class Real>
struct TrackingError {
    Real x_m;        ///< x_e, ahead of the robot [m]
    Real y_m;        ///< y_e, to its left [m]
    Real theta_rad;  ///< th_e = th_g - th [rad], not wrapped (the sketch does not wrap)
};

/// The robot-frame velocity the control law asks for.
template <class Real>
struct VelocityCommand {
    Real v_m_s;
    Real omega_rad_s;
};

/// eq. (12) in the sketch's order: errx = x_g - x, ..., errxr = cos(th) errx + sin(th) erry.
template <class Real>
TrackingError<Real> tracking_error(Real goal_x_m, Real goal_y_m, Real goal_theta_rad,
                                   const PoseEstimate<Real>& robot) {
    const Real errx = goal_x_m - robot.x_m;
    const Real erry = goal_y_m - robot.y_m;
    const Real etheta = goal_theta_rad - robot.theta_rad;
    const Real c = std::cos(robot.theta_rad);
    const Real s = std::sin(robot.theta_rad);
    return {c * errx + s * erry, -s * errx + c * erry, etheta};
}

/// eq. (14) with the gains converted to Real (as the sketch converts its int
/// gains to float in `kx*errxr`).
template <class Real>
VelocityCommand<Real> kanayama_law(const TrackingError<Real>& e, const Gains& g) {
    const Real kx = static_cast<Real>(g.kx);
    const Real ky = static_cast<Real>(g.ky);
    const Real kw = static_cast<Real>(g.kw);
    const Real vref = static_cast<Real>(g.vref_m_s);
    const Real wref = static_cast<Real>(g.wref_rad_s);
    return {vref * std::cos(e.theta_rad) + kx * e.x_m,
            wref + vref * (ky * e.y_m + kw * std::sin(e.theta_rad))};
}

/// eq. (15). NaN when K_y <= 0 (the function is not defined there).
double lyapunov(const TrackingError<double>& e, double ky);

/// eq. (16): the rate of eq. (15) along the ideal closed loop.
double lyapunov_rate(const TrackingError<double>& e, const Gains& g);

}  // namespace ddmr::hostsim
