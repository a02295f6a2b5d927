#include "calibrate/log_residual.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ddmr::calibrate {

CountCell count_cell(long long c) {
    if (c > 0) return {static_cast<double>(c), static_cast<double>(c) + 1.0};
    if (c < 0) return {static_cast<double>(c) - 1.0, static_cast<double>(c)};
    return {-1.0, 1.0};
}

double cell_residual_m(double sim_m, uint8_t byte, double counts_per_m) {
    if (!std::isfinite(sim_m)) return std::numeric_limits<double>::infinity();
    const double s = sim_m * counts_per_m;
    // A diverged run (kilometres): the distance itself is the right size.
    if (std::fabs(s) > 1e12) return std::fabs(sim_m);
    // The cells of `byte` nearest s: c = byte + 256 m around trunc(s).
    const double t = std::trunc(s);
    const auto m0 = static_cast<long long>(std::floor((t - byte) / 256.0));
    double best = std::numeric_limits<double>::infinity();
    for (long long m = m0 - 1; m <= m0 + 2; ++m) {
        const long long c = byte + 256 * m;
        const CountCell cell = count_cell(c);
        best = std::min(best, std::max({cell.lo - s, 0.0, s - cell.hi}));
    }
    return best / counts_per_m;
}

double cell_centre_residual_m(double sim_m, uint8_t byte, double counts_per_m) {
    if (!std::isfinite(sim_m)) return std::numeric_limits<double>::infinity();
    const double s = sim_m * counts_per_m;
    if (std::fabs(s) > 1e12) return sim_m;
    const double t = std::trunc(s);
    const auto m0 = static_cast<long long>(std::floor((t - byte) / 256.0));
    double best = std::numeric_limits<double>::infinity();
    for (long long m = m0 - 1; m <= m0 + 2; ++m) {
        const CountCell cell = count_cell(byte + 256 * m);
        const double d = s - 0.5 * (cell.lo + cell.hi);
        if (std::fabs(d) < std::fabs(best)) best = d;
    }
    return best / counts_per_m;
}

double soft_l1(double r, double s) {
    if (!(s > 0.0)) throw std::invalid_argument("soft_l1: the scale must be > 0");
    const double z = r / s;
    return 2.0 * s * s * (std::sqrt(1.0 + z * z) - 1.0);
}

}  // namespace ddmr::calibrate
