#include "plant/motor_stepper.hpp"

#include "plant/root_find.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddmr::plant {

namespace {

double sgn(double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); }

/// The entry of a small round-robin cache keyed by step length `h` (the
/// entries' `h` member): the one holding `h`, or the oldest one, refilled
/// by `fill` for `h`.
template <class Entry, std::size_t N, class Fill>
const Entry& recent(std::array<Entry, N>& cache, std::size_t& next, double h, const Fill& fill) {
    for (const Entry& c : cache) {
        if (c.h == h) return c;
    }
    Entry& c = cache[next];
    next = (next + 1) % N;
    c.h = h;
    fill(c);
    return c;
}

}  // namespace

MotorStepper::MotorStepper(const DcMotorParams& p)
    : p_(p),
      coast_time_constant_(p.inertia_kg_m2 / p.viscous_friction_N_m_s_per_rad),
      coast_stall_speed_(p.coulomb_friction_N_m / p.viscous_friction_N_m_s_per_rad) {
    configure(0.0);
}

void MotorStepper::configure(double series_resistance_ohm) {
    if (series_resistance_ohm == series_ohm_) return;
    series_ohm_ = series_resistance_ohm;
    r_total_ohm_ = p_.resistance_ohm + series_resistance_ohm;
    const DcMotorParams& p = p_;
    // eq. (9f), one motor's block.
    a_ << -r_total_ohm_ / p.inductance_H, -p.back_emf_V_s_per_rad / p.inductance_H,
        p.torque_N_m_per_A / p.inertia_kg_m2, -p.viscous_friction_N_m_s_per_rad / p.inertia_kg_m2;
    // det(A) = (R_a F + K_t K_a) / (L_a J) > 0 for valid parameters.
    a_inv_ = a_.inverse();
    half_trace_ = 0.5 * a_.trace();
    discriminant_ = half_trace_ * half_trace_ - a_.determinant();
    max_segment_s_ = discriminant_ < 0.0 ? kPi / std::sqrt(-discriminant_)
                                         : std::numeric_limits<double>::infinity();
    for (CacheEntry& c : cache_) c.h = -1.0;
}

double MotorStepper::slow_eigenvalue_real() const {
    return discriminant_ > 0.0 ? half_trace_ + std::sqrt(discriminant_) : half_trace_;
}

double MotorStepper::fast_eigenvalue_real() const {
    return discriminant_ > 0.0 ? half_trace_ - std::sqrt(discriminant_) : half_trace_;
}

Eigen::Matrix2d MotorStepper::transition(double t) const {
    // A = m I + N with N^2 = q I, so e^{A t} = e^{m t} (c(t) I + s(t) N) where
    // (c, s) = (cosh, sinh/delta)(delta t), (cos, sin/beta)(beta t) or (1, t).
    const Eigen::Matrix2d n = a_ - half_trace_ * Eigen::Matrix2d::Identity();
    const Eigen::Matrix2d id = Eigen::Matrix2d::Identity();
    const double q = discriminant_;
    if (q > 0.0) {
        const double delta = std::sqrt(q);
        if (delta * t > 1.0) {
            // Two-exponential form: no overflow for long steps.
            const double e1 = std::exp((half_trace_ + delta) * t);
            const double e2 = std::exp((half_trace_ - delta) * t);
            return (e1 * (delta * id + n) + e2 * (delta * id - n)) / (2.0 * delta);
        }
        const double x = delta * t;
        return std::exp(half_trace_ * t) * (std::cosh(x) * id + (std::sinh(x) / delta) * n);
    }
    if (q < 0.0) {
        const double beta = std::sqrt(-q);
        return std::exp(half_trace_ * t) *
               (std::cos(beta * t) * id + (std::sin(beta * t) / beta) * n);
    }
    return std::exp(half_trace_ * t) * (id + t * n);
}

const MotorStepper::CacheEntry& MotorStepper::cached(double h) {
    return recent(cache_, cache_next_, h, [&](CacheEntry& c) {
        c.e = transition(h);
        c.g = a_inv_ * (c.e - Eigen::Matrix2d::Identity());
    });
}

const MotorStepper::CoastEntry& MotorStepper::coast_decay(double h) {
    return recent(coast_cache_, coast_next_, h, [&](CoastEntry& c) {
        c.decay = std::exp(-h / coast_time_constant_);
        c.one_minus_decay = -std::expm1(-h / coast_time_constant_);
    });
}

void MotorStepper::coast(const DcMotorState& x, double tau, MotorSegment& seg) {
    seg.start = x;
    seg.end = x;
    seg.duration_s = tau;
    if (x.speed_rad_s == 0.0) {
        seg.regime = MotorRegime::stopped;
        return;
    }
    // I = 0: J dw/dt = -F w - T_c sgn(w); w(t) = w_ss + (w0 - w_ss) e^{-F t / J}
    // with w_ss = -sgn(w) T_c / F.
    seg.regime = MotorRegime::coasting;
    const double w_ss = -sgn(x.speed_rad_s) * coast_stall_speed_;
    seg.x_ss = Eigen::Vector2d(0.0, w_ss);
    const double dw = x.speed_rad_s - w_ss;
    // w reaches 0 where |dw| e^{-F t / J} = T_c / F: within the segment when
    // the decay over it gets there.
    const CoastEntry* d = &coast_decay(tau);
    const bool stops = coast_stall_speed_ > 0.0 && d->decay * std::abs(dw) <= coast_stall_speed_;
    if (stops) {
        seg.duration_s =
            std::min(std::log(std::abs(dw) / coast_stall_speed_) * coast_time_constant_, tau);
        d = &coast_decay(seg.duration_s);
    }
    seg.end.speed_rad_s = stops ? 0.0 : w_ss + dw * d->decay;
    seg.end.angle_rad =
        x.angle_rad + w_ss * seg.duration_s + dw * d->one_minus_decay * coast_time_constant_;
}

double MotorStepper::effective_voltage(const DcMotorState& x, const MotorTerminal& u) const {
    if (u.kind == MotorTerminal::Kind::driven) return u.voltage_V;
    return -sgn(x.current_A) * u.clamp_V;
}

MotorRegime MotorStepper::classify(const DcMotorState& x, const MotorTerminal& u) const {
    const bool open = u.kind == MotorTerminal::Kind::open;
    if (open && x.current_A == 0.0) {
        return x.speed_rad_s == 0.0 ? MotorRegime::stopped : MotorRegime::coasting;
    }
    if (x.speed_rad_s != 0.0) return MotorRegime::moving;
    const double torque = p_.torque_N_m_per_A * std::abs(x.current_A);
    if (torque < p_.coulomb_friction_N_m) return MotorRegime::stuck;
    if (torque > p_.coulomb_friction_N_m) return MotorRegime::moving;
    // |K_t I| == T_c exactly: it breaks away only if |I| is growing.
    const double di = (effective_voltage(x, u) - r_total_ohm_ * x.current_A) / p_.inductance_H;
    const bool growing = x.current_A != 0.0 ? x.current_A * di > 0.0 : di != 0.0;
    return growing ? MotorRegime::moving : MotorRegime::stuck;
}

double MotorStepper::moving_sign(const DcMotorState& x, const MotorTerminal& u) const {
    if (x.speed_rad_s != 0.0) return sgn(x.speed_rad_s);
    if (x.current_A != 0.0) return sgn(x.current_A);
    return sgn(effective_voltage(x, u));
}

DcMotorState MotorStepper::state_at(const MotorSegment& seg, double tau) const {
    DcMotorState s = seg.start;
    switch (seg.regime) {
        case MotorRegime::moving: {
            const Eigen::Vector2d x0(seg.start.current_A, seg.start.speed_rad_s);
            const Eigen::Vector2d d0 = x0 - seg.x_ss;
            const Eigen::Matrix2d e = transition(tau);
            const Eigen::Vector2d x = seg.x_ss + e * d0;
            const Eigen::Vector2d integral =
                seg.x_ss * tau + a_inv_ * ((e - Eigen::Matrix2d::Identity()) * d0);
            s.current_A = x(0);
            s.speed_rad_s = x(1);
            s.angle_rad = seg.start.angle_rad + integral(1);
            break;
        }
        case MotorRegime::stuck: {
            const double k = std::exp(-tau * r_total_ohm_ / p_.inductance_H);
            s.current_A = seg.x_ss(0) + (seg.start.current_A - seg.x_ss(0)) * k;
            break;
        }
        case MotorRegime::coasting: {
            const double rate = p_.viscous_friction_N_m_s_per_rad / p_.inertia_kg_m2;
            const double w_ss = seg.x_ss(1);
            const double dw = seg.start.speed_rad_s - w_ss;
            s.speed_rad_s = w_ss + dw * std::exp(-rate * tau);
            s.angle_rad = seg.start.angle_rad + w_ss * tau + dw * (-std::expm1(-rate * tau)) / rate;
            break;
        }
        case MotorRegime::stopped:
            break;
    }
    return s;
}

/// The first event of a moving segment before `tau_s`: w reaches 0 (1), or,
/// bridge off, I reaches 0 (2); 0 and `tau_s` when none. `x0`/`x1`: the state at
/// the segment's start and at `tau_s`; `b`: the input term; `s`: the sign w moves with.
MotorStepper::MovingEvent MotorStepper::moving_event(const MotorSegment& seg, const Eigen::Vector2d& x0,
                                                     const Eigen::Vector2d& x1, const Eigen::Vector2d& b,
                                                     double s, double tau_s, bool open) const {
    const Eigen::Vector2d d0 = x0 - seg.x_ss;
    auto eval = [&](double tt) -> Eigen::Vector2d {
        return seg.x_ss + transition(tt) * d0;
    };
    const double tau = tau_s;
    double t_event = tau;
    int event = 0;  // 1: w reaches 0, 2: I reaches 0 (bridge off)
    // g(t) = s w(t) starts >= 0; find its first downward zero.
    auto w_fn = [&](double tt) {
        const Eigen::Vector2d xx = eval(tt);
        const Eigen::Vector2d dx = a_ * xx + b;
        return std::pair<double, double>{xx(1), dx(1)};
    };
    auto dw_fn = [&](double tt) {
        const Eigen::Vector2d xx = eval(tt);
        const Eigen::Vector2d dx = a_ * xx + b;
        const Eigen::Vector2d ddx = a_ * dx;
        return std::pair<double, double>{dx(1), ddx(1)};
    };
    const double dw0 = (a_ * x0 + b)(1);
    const double dw1 = (a_ * x1 + b)(1);
    if (s * x1(1) <= 0.0) {
        if (x0(1) != 0.0) {
            t_event = find_root(w_fn, 0.0, tau, s);
        } else {
            // Starts at rest: it first moves along s, turns, crosses back.
            const double te = find_root(dw_fn, 0.0, tau, s);
            t_event = find_root(w_fn, te, tau, s);
        }
        event = 1;
    } else if (s * dw0 < 0.0 && s * dw1 > 0.0) {
        // One minimum of s w inside: does it dip below 0?
        const double te = find_root(dw_fn, 0.0, tau, -s);
        if (s * eval(te)(1) <= 0.0) {
            t_event = find_root(w_fn, 0.0, te, s);
            event = 1;
        }
    }
    if (open) {
        // Through the diodes |I| falls monotonically (|K_a w| < clamp).
        const double si = sgn(x0(0));
        const Eigen::Vector2d xe = event ? eval(t_event) : x1;
        if (si * xe(0) <= 0.0) {
            auto i_fn = [&](double tt) {
                const Eigen::Vector2d xx = eval(tt);
                const Eigen::Vector2d dx = a_ * xx + b;
                return std::pair<double, double>{xx(0), dx(0)};
            };
            t_event = find_root(i_fn, 0.0, t_event, si);
            event = 2;
        }
    }
    return MovingEvent{t_event, event};
}

/// The moving regime: the linear system in closed form, up to `tau_s` or its first event.
MotorStepper::SegmentOutcome MotorStepper::moving_segment(const DcMotorState& x, const MotorTerminal& u,
                                                          double tau_s, bool last, MotorSegment& seg) {
    const bool open = u.kind == MotorTerminal::Kind::open;
    const double l = p_.inductance_H;
    const double tc = p_.coulomb_friction_N_m;
    const double jm = p_.inertia_kg_m2;
    double tau = tau_s;
    DcMotorState end = x;
    const double v = effective_voltage(x, u);
    const double s = moving_sign(x, u);
    const Eigen::Vector2d b(v / l, -s * tc / jm);
    seg.x_ss = -(a_inv_ * b);
    const Eigen::Vector2d x0(x.current_A, x.speed_rad_s);
    const Eigen::Vector2d d0 = x0 - seg.x_ss;
    if (!last) tau = std::min(tau, max_segment_s_);
    const CacheEntry& c0 = cached(tau);
    Eigen::Vector2d x1 = seg.x_ss + c0.e * d0;
    Eigen::Matrix2d g = c0.g;
    MovingEvent ev{tau, 0};
    if (!last) ev = moving_event(seg, x0, x1, b, s, tau, open);
    if (ev.kind != 0) {
        tau = ev.t_s;
        const Eigen::Matrix2d e = transition(tau);
        x1 = seg.x_ss + e * d0;
        g = a_inv_ * (e - Eigen::Matrix2d::Identity());
    }
    const Eigen::Vector2d integral = seg.x_ss * tau + g * d0;
    end.current_A = x1(0);
    end.speed_rad_s = x1(1);
    end.angle_rad = x.angle_rad + integral(1);
    if (ev.kind == 1) end.speed_rad_s = 0.0;
    if (ev.kind == 2) end.current_A = 0.0;
    return SegmentOutcome{tau, end, integral(0), false};
}

/// The stuck regime (w = 0): L_a dI/dt = V - R_a I, first order towards
/// I_ss = V / R_a, up to `tau_s` or the current that breaks the friction away
/// (or, bridge off, that decays to 0).
MotorStepper::SegmentOutcome MotorStepper::stuck_segment(const DcMotorState& x, const MotorTerminal& u,
                                                         double tau_s, bool last, MotorSegment& seg) const {
    const bool open = u.kind == MotorTerminal::Kind::open;
    const double r = r_total_ohm_;
    const double l = p_.inductance_H;
    const double kt = p_.torque_N_m_per_A;
    const double tc = p_.coulomb_friction_N_m;
    double tau = tau_s;
    DcMotorState end = x;
    const double v = effective_voltage(x, u);
    const double i_ss = v / r;
    seg.x_ss = Eigen::Vector2d(i_ss, 0.0);
    const double i0 = x.current_A;
    const double rate = r / l;
    double target = 0.0;
    int event = 0;
    if (!last && i0 != i_ss) {
        const double i_break = sgn(i_ss) * tc / kt;
        if (!open && std::abs(i_ss) > tc / kt) {
            target = i_break;
            event = 1;
        } else if (open) {
            target = 0.0;  // decays to 0 through the diodes, then opens
            event = 2;
        }
    }
    if (event != 0) {
        // i(t) = i_ss + (i0 - i_ss) e^{-rate t} = target
        const double ratio = (target - i_ss) / (i0 - i_ss);
        const double t_hit = ratio > 0.0 && ratio <= 1.0 ? -std::log(ratio) / rate
                                                         : std::numeric_limits<double>::infinity();
        if (t_hit <= tau) {
            tau = t_hit;
        } else {
            event = 0;
        }
    }
    const double k = std::exp(-rate * tau);
    end.current_A = event != 0 ? target : i_ss + (i0 - i_ss) * k;
    const double charge = i_ss * tau + (i0 - i_ss) * (-std::expm1(-rate * tau)) / rate;
    return SegmentOutcome{tau, end, charge, event == 1};
}

void MotorStepper::advance(DcMotorState& x, const MotorTerminal& u, double h,
                           MotorStepResult& out) {
    out.segment_count = 0;
    out.charge_C = 0.0;
    out.supply_charge_C = 0.0;
    configure(u.series_resistance_ohm);

    double t = 0.0;
    bool force_moving = false;
    while (t < h) {
        const bool last = out.segment_count + 1 == MotorStepResult::kMaxSegments;
        const double remaining = h - t;
        MotorSegment& seg = out.segments[out.segment_count++];
        seg.t0_s = t;
        seg.start = x;
        seg.regime = force_moving ? MotorRegime::moving : classify(x, u);
        force_moving = false;
        SegmentOutcome o{remaining, x, 0.0, false};

        switch (seg.regime) {
            case MotorRegime::moving:
                o = moving_segment(x, u, remaining, last, seg);
                break;
            case MotorRegime::stuck:
                o = stuck_segment(x, u, remaining, last, seg);
                force_moving = o.force_moving;
                break;
            case MotorRegime::coasting: {
                coast(x, remaining, seg);
                o.tau_s = seg.duration_s;
                o.end = seg.end;
                break;
            }
            case MotorRegime::stopped:
                break;
        }
        const double tau = o.tau_s;
        const double charge = o.charge_C;
        const DcMotorState end = o.end;
        seg.duration_s = tau;
        seg.end = end;
        out.charge_C += charge;
        if (u.kind == MotorTerminal::Kind::driven) {
            out.supply_charge_C += u.supply_factor * charge;
        } else {
            // Bridge off: the decaying current flows back into the battery.
            out.supply_charge_C -= std::abs(charge);
        }
        x = end;
        // The last segment runs to the end of the step, even past an event
        // (a step with more events than kMaxSegments: never seen in practice).
        t = (seg.regime == MotorRegime::stopped || last) ? h : t + tau;
        if (t >= h) {
            seg.duration_s = h - seg.t0_s;
        }
    }
}

}  // namespace ddmr::plant
