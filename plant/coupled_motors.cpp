#include "plant/coupled_motors.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>

#include "plant/root_find.hpp"

namespace ddmr::plant {

namespace {

double sgn(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

/// phi(z) = (e^z - 1) / z, with its series near 0 (no cancellation).
std::complex<double> phi(std::complex<double> z) {
    if (std::abs(z) < 1e-3) return 1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0));
    return (std::exp(z) - 1.0) / z;
}

/// Worst condition number of V accepted: beyond it e^{A t} = V e^{Lambda t}
/// V^{-1} loses more than ~8 of its 16 digits (A near-defective, e.g. a
/// critically damped motor) and the motor-by-motor solution is used instead.
constexpr double kMaxCondition = 1e8;

}  // namespace

CoupledMotorStepper::CoupledMotorStepper(const DcMotorParams& motor1, const DcMotorParams& motor2)
    : p_{motor1, motor2} {}

Eigen::Matrix4d CoupledMotorStepper::system_matrix(double s1, double s2, double rb, double r1,
                                                   double r2) const {
    Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
    const std::array<double, 2> s{s1, s2};
    const std::array<double, 2> r{r1, r2};
    for (std::size_t m = 0; m < 2; ++m) {
        const DcMotorParams& p = p_[m];
        const Eigen::Index i = static_cast<Eigen::Index>(2 * m);
        // R_a + 0.0 == R_a: without bridge resistance A is the thesis robot's, bit for bit.
        a(i, i) = -(p.resistance_ohm + r[m]) / p.inductance_H;
        a(i, i + 1) = -p.back_emf_V_s_per_rad / p.inductance_H;
        for (std::size_t n = 0; n < 2; ++n) {
            a(i, static_cast<Eigen::Index>(2 * n)) -= s[m] * rb * s[n] / p.inductance_H;
        }
        a(i + 1, i) = p.torque_N_m_per_A / p.inertia_kg_m2;
        a(i + 1, i + 1) = -p.viscous_friction_N_m_s_per_rad / p.inertia_kg_m2;
    }
    return a;
}

void CoupledMotorStepper::build(Config& c) const {
    c.a = system_matrix(c.s1, c.s2, c.rb, c.r1, c.r2);
    c.h = {-1.0, -1.0};
    c.next_h = 0;
    // det(A) > 0 for valid parameters (each block's det is (R F + K_t K_a) / (L J)
    // and the coupling only adds resistance), so A is invertible.
    c.a_inv = c.a.inverse();
    const Eigen::EigenSolver<Eigen::Matrix4d> es(c.a);
    c.usable = false;
    if (es.info() != Eigen::Success) return;
    c.lambda = es.eigenvalues();
    c.v = es.eigenvectors();
    const Eigen::PartialPivLU<Eigen::Matrix4cd> lu(c.v);
    c.v_inv = lu.inverse();
    const double cond = c.v.cwiseAbs().rowwise().sum().maxCoeff() *
                        c.v_inv.cwiseAbs().rowwise().sum().maxCoeff();
    c.usable = std::isfinite(cond) && cond < kMaxCondition && c.a_inv.allFinite();
    c.max_imag = c.lambda.imag().cwiseAbs().maxCoeff();
    c.real_modes = c.max_imag == 0.0;
    if (c.real_modes) {
        c.v_real = c.v.real();
        c.v_inv_real = c.v_inv.real();
    }
}

std::size_t CoupledMotorStepper::config_for(const std::array<CoupledTerminal, 2>& u, double rb) {
    const double s1 = u[0].supply_factor;
    const double s2 = u[1].supply_factor;
    const double r1 = u[0].series_resistance_ohm;
    const double r2 = u[1].series_resistance_ohm;
    auto matches = [&](const Config& c) {
        return c.rb == rb && c.s1 == s1 && c.s2 == s2 && c.r1 == r1 && c.r2 == r2;
    };
    if (matches(configs_[last_config_])) return last_config_;
    for (std::size_t k = 0; k < kConfigs; ++k) {
        if (matches(configs_[k])) return last_config_ = k;
    }
    const std::size_t k = next_config_;
    last_config_ = k;
    next_config_ = (next_config_ + 1) % kConfigs;
    Config& c = configs_[k];
    c.s1 = s1;
    c.s2 = s2;
    c.rb = rb;
    c.r1 = r1;
    c.r2 = r2;
    build(c);
    return k;
}

std::size_t CoupledMotorStepper::transition_for(Config& c, double h) {
    for (std::size_t k = 0; k < c.h.size(); ++k) {
        if (c.h[k] == h) return k;
    }
    const std::size_t k = c.next_h;
    c.next_h = (c.next_h + 1) % c.h.size();
    c.h[k] = h;
    Eigen::Vector4cd ex;
    Eigen::Vector4cd in;
    for (Eigen::Index j = 0; j < 4; ++j) {
        const std::complex<double> z = c.lambda(j) * h;
        ex(j) = std::exp(z);
        in(j) = h * phi(z);
    }
    c.e[k] = (c.v * ex.asDiagonal() * c.v_inv).real();
    c.g[k] = (c.v * in.asDiagonal() * c.v_inv).real();
    return k;
}

double CoupledMotorStepper::advance(std::array<DcMotorState, 2>& x,
                                    const std::array<CoupledTerminal, 2>& u, double rb, double h,
                                    CoupledSegment& seg, double& supply_charge_C) {
    // Both shafts must be turning, and a diode current must be flowing.
    std::array<double, 2> w_sign{};
    for (std::size_t m = 0; m < 2; ++m) {
        w_sign[m] = sgn(x[m].speed_rad_s);
        if (w_sign[m] == 0.0) return 0.0;
        if (u[m].diode && x[m].current_A == 0.0) return 0.0;
    }
    const std::size_t ci = config_for(u, rb);
    Config& c = configs_[ci];
    if (!c.usable) return 0.0;
    // Complex eigenvalues: a speed could cross zero more than once in one step.
    if (c.max_imag * h > 3.0) return 0.0;
    const std::size_t ti = transition_for(c, h);

    Eigen::Vector4d b;
    for (std::size_t m = 0; m < 2; ++m) {
        const DcMotorParams& p = p_[m];
        const Eigen::Index i = static_cast<Eigen::Index>(2 * m);
        b(i) = u[m].supply_factor * u[m].emf_V / p.inductance_H;
        b(i + 1) = -w_sign[m] * p.coulomb_friction_N_m / p.inertia_kg_m2;
    }
    const Eigen::Vector4d x0(x[0].current_A, x[0].speed_rad_s, x[1].current_A, x[1].speed_rad_s);
    seg.x_ss = -(c.a_inv * b);
    const Eigen::Vector4d d0 = x0 - seg.x_ss;
    seg.d0 = d0;
    seg.modes_ready = false;
    seg.config = ci;
    Eigen::Vector4d x1 = seg.x_ss + c.e[ti] * d0;

    // Regime changes inside the step: the first one ends the segment there.
    //   a speed reaches 0 (the shaft sticks or reverses: sgn(w) in b changes);
    //   a diode current reaches 0 (the motor is then open-circuit).
    auto component = [&](Eigen::Index k, int order) {
        return [&, k, order](double tau) { return component_at(seg, k, order, tau); };
    };
    double t_event = h;
    Eigen::Index zeroed = -1;  // the state component that reaches 0 at t_event
    for (std::size_t m = 0; m < 2; ++m) {
        const Eigen::Index i = static_cast<Eigen::Index>(2 * m);
        const double s = w_sign[m];
        // dw/dt at the start and at the end of the step.
        const double dw0 = c.a.row(i + 1).dot(x0) + b(i + 1);
        const double dw1 = c.a.row(i + 1).dot(x1) + b(i + 1);
        double t_w = h + 1.0;
        if (!(s * x1(i + 1) > 0.0)) {
            t_w = find_root(component(i + 1, 0), 0.0, h, s);
        } else if (s * dw0 < 0.0 && s * dw1 > 0.0 && !keeps_sign(seg, i + 1, s, x0(i + 1), dw0, h)) {
            // One minimum of s w inside, and the bound cannot rule out that
            // it dips through zero: find it.
            const double te = find_root(component(i + 1, 1), 0.0, h, -s);
            if (!(s * component_at(seg, i + 1, 0, te).first > 0.0)) {
                t_w = find_root(component(i + 1, 0), 0.0, te, s);
            }
        }
        if (t_w < t_event) {
            t_event = t_w;
            zeroed = i + 1;
        }
        // Through the diodes |I| falls monotonically (|K_a w| < clamp).
        if (u[m].diode && !(sgn(x0(i)) * x1(i) > 0.0)) {
            const double t_i = find_root(component(i, 0), 0.0, h, sgn(x0(i)));
            if (t_i < t_event) {
                t_event = t_i;
                zeroed = i;
            }
        }
    }
    if (!(t_event > 0.0)) return 0.0;  // a root at the very start: let the caller decide
    Eigen::Vector4d integral;
    if (zeroed < 0) {
        integral = seg.x_ss * h + c.g[ti] * d0;
    } else {
        resolve_modes(seg);
        const Eigen::Vector4cd e = exp_modes(c, t_event);
        x1 = seg.x_ss + (c.v * e.cwiseProduct(seg.modes)).real();
        x1(zeroed) = 0.0;
        Eigen::Vector4cd in;
        for (Eigen::Index j = 0; j < 4; ++j) {
            in(j) = t_event * phi(c.lambda(j) * t_event) * seg.modes(j);
        }
        integral = seg.x_ss * t_event + (c.v * in).real();
    }
    seg.duration_s = t_event;
    seg.start = x;
    for (std::size_t m = 0; m < 2; ++m) {
        const Eigen::Index i = static_cast<Eigen::Index>(2 * m);
        x[m].current_A = x1(i);
        x[m].speed_rad_s = x1(i + 1);
        x[m].angle_rad += integral(i + 1);
    }
    supply_charge_C = u[0].supply_factor * integral(0) + u[1].supply_factor * integral(2);
    return t_event;
}

void CoupledMotorStepper::resolve_modes(const CoupledSegment& seg) const {
    if (seg.modes_ready) return;
    const Config& c = configs_[seg.config];
    if (c.real_modes) {
        const Eigen::Vector4d modes = c.v_inv_real * seg.d0;
        seg.modes = modes.cast<std::complex<double>>();
        seg.coef = (c.v_real * modes.asDiagonal()).cast<std::complex<double>>();
    } else {
        seg.modes = c.v_inv * seg.d0.cast<std::complex<double>>();
        seg.coef = c.v * seg.modes.asDiagonal();
    }
    seg.modes_ready = true;
}

bool CoupledMotorStepper::keeps_sign(const CoupledSegment& seg, Eigen::Index k, double s,
                                     double x0, double dx0, double h) const {
    resolve_modes(seg);
    const Config& c = configs_[seg.config];
    double bound = 0.0;  // >= |x_k''| on [0, h]
    for (Eigen::Index j = 0; j < 4; ++j) {
        const std::complex<double> lambda = c.lambda(j);
        bound += std::abs(seg.coef(k, j)) * std::norm(lambda) * std::exp(std::max(lambda.real(), 0.0) * h);
    }
    // The bound is concave in t and s x0 > 0: its minimum on [0, h] is at h.
    return s * (x0 + dx0 * h) - 0.5 * bound * h * h > 0.0;
}

Eigen::Vector4cd CoupledMotorStepper::exp_modes(const Config& c, double tau) {
    Eigen::Vector4cd e;
    for (Eigen::Index j = 0; j < 4; ++j) e(j) = std::exp(c.lambda(j) * tau);
    return e;
}

std::pair<double, double> CoupledMotorStepper::component_at(const CoupledSegment& seg,
                                                            Eigen::Index k, int order,
                                                            double tau) const {
    resolve_modes(seg);
    const Config& c = configs_[seg.config];
    double value = order == 0 ? seg.x_ss(k) : 0.0;
    double slope = 0.0;
    for (Eigen::Index j = 0; j < 4; ++j) {
        const std::complex<double> lambda = c.lambda(j);
        if (lambda.imag() == 0.0) {
            const double l = lambda.real();
            const double term = seg.coef(k, j).real() * std::exp(l * tau) * (order == 0 ? 1.0 : l);
            value += term;
            slope += term * l;
        } else {
            const std::complex<double> term =
                seg.coef(k, j) * std::exp(lambda * tau) * (order == 0 ? 1.0 : lambda);
            value += term.real();
            slope += (term * lambda).real();
        }
    }
    return {value, slope};
}

DcMotorState CoupledMotorStepper::state_at(const CoupledSegment& seg, std::size_t m,
                                           double tau) const {
    resolve_modes(seg);
    const Config& c = configs_[seg.config];
    const Eigen::Index i = static_cast<Eigen::Index>(2 * m);
    double cur = 0.0;
    double speed = 0.0;
    double turn = 0.0;
    for (Eigen::Index j = 0; j < 4; ++j) {
        const std::complex<double> lambda = c.lambda(j);
        const std::complex<double> ci = seg.coef(i, j);
        const std::complex<double> cw = seg.coef(i + 1, j);
        if (lambda.imag() == 0.0) {
            // Real mode (the usual case): real arithmetic only.
            const double z = lambda.real() * tau;
            const double e = std::exp(z);
            const double integral = std::abs(z) < 1e-3 ? tau * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0)))
                                                       : (e - 1.0) / lambda.real();
            cur += ci.real() * e;
            speed += cw.real() * e;
            turn += cw.real() * integral;
        } else {
            const std::complex<double> z = lambda * tau;
            const std::complex<double> e = std::exp(z);
            const std::complex<double> integral =
                std::abs(z) < 1e-3 ? tau * phi(z) : (e - 1.0) / lambda;
            cur += (ci * e).real();
            speed += (cw * e).real();
            turn += (cw * integral).real();
        }
    }
    DcMotorState s;
    s.current_A = seg.x_ss(i) + cur;
    s.speed_rad_s = seg.x_ss(i + 1) + speed;
    s.angle_rad = seg.start[m].angle_rad + seg.x_ss(i + 1) * tau + turn;
    return s;
}

}  // namespace ddmr::plant
