#pragma once
// Clipping a segment's parameter interval to a half-plane (Liang-Barsky), for
// the world's cones (world.cpp) and the body's footprint (body_contact.cpp).

#include <algorithm>

namespace ddmr::plant {

/// Narrows [lo, hi] to the parameters t where f(t) = f0 + t df >= 0 (f
/// linear along the segment); false when nothing is left.
inline bool clip_to_half_plane(double f0, double df, double& lo, double& hi) {
    if (df == 0.0) return f0 >= 0.0;
    const double t = -f0 / df;
    if (df > 0.0) {
        lo = std::max(lo, t);
    } else {
        hi = std::min(hi, t);
    }
    return lo <= hi;
}

}  // namespace ddmr::plant
