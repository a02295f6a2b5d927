#pragma once
// Bracketed root finding on exact solutions (event times, encoder edges).

#include <algorithm>
#include <cmath>
#include <limits>

namespace ddmr::plant {

/// Root of f on [a, b], where f(a) has the sign `sign_a` (+1 or -1; declared,
/// so a root exactly at `a` is skipped) and f(b) has the other sign or is 0.
/// `f(t)` returns {value, derivative}. Safeguarded Newton: iterates that would
/// leave the bracket are replaced by bisection, so it always converges;
/// near the root it converges quadratically. Returns a time within a few ulp
/// of the root, never outside [a, b].
template <class F>
double find_root(const F& f, double a, double b, double sign_a) {
    double t = b;
    for (int k = 0; k < 200; ++k) {
        const auto [v, dv] = f(t);
        if (v == 0.0) return t;
        if ((v > 0.0) == (sign_a > 0.0)) {
            a = t;
        } else {
            b = t;
        }
        const double tol = 4.0 * std::numeric_limits<double>::epsilon() * std::max(b, 1e-9);
        if (b - a <= tol) break;
        double next = dv != 0.0 ? t - v / dv : 0.5 * (a + b);
        if (!(next > a && next < b)) next = 0.5 * (a + b);
        if (std::abs(next - t) <= tol) return next;
        t = next;
    }
    return b;
}

}  // namespace ddmr::plant
