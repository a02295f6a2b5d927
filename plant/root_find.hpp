#pragma once
// Bracketed root finding on exact solutions (event times, encoder edges).

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddmr::plant {

/// Event and edge times are solved to this [s]: 1/62500 of an AVR cycle at
/// 16 MHz, far below anything the HIL resolves, and above the rounding noise
/// of the exact solutions (near a root, Newton steps on that noise would
/// otherwise shrink the bracket by bisection down to the last ulp).
inline constexpr double kRootTolerance_s = 1e-12;

/// Root of f on [a, b], where f(a) has the sign `sign_a` (+1 or -1; declared,
/// so a root exactly at `a` is skipped) and f(b) has the other sign or is 0.
/// `f(t)` returns {value, derivative}. Safeguarded Newton from `first_guess`
/// (b when it is not in (a, b]): iterates that would leave the bracket are
/// replaced by bisection, so it always converges; near the root it converges
/// quadratically. Returns a time within kRootTolerance_s (or a few ulp of the
/// root, whichever is larger) of the root, never outside [a, b].
template <class F>
double find_root(const F& f, double a, double b, double sign_a, double first_guess) {
    double t = first_guess > a && first_guess <= b ? first_guess : b;
    for (int k = 0; k < 200; ++k) {
        const auto [v, dv] = f(t);
        if (v == 0.0) return t;
        if ((v > 0.0) == (sign_a > 0.0)) {
            a = t;
        } else {
            b = t;
        }
        const double tol = std::max(4.0 * std::numeric_limits<double>::epsilon() * b, kRootTolerance_s);
        if (b - a <= tol) break;
        double next = dv != 0.0 ? t - v / dv : 0.5 * (a + b);
        if (!(next > a && next < b)) next = 0.5 * (a + b);
        if (std::abs(next - t) <= tol) return next;
        t = next;
    }
    return b;
}

/// find_root() starting from b.
template <class F>
double find_root(const F& f, double a, double b, double sign_a) {
    return find_root(f, a, b, sign_a, b);
}

}  // namespace ddmr::plant
