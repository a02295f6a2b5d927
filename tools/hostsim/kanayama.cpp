#include "tools/hostsim/kanayama.hpp"

#include <limits>
#include <stdexcept>
#include <string>

namespace ddmr::hostsim {

namespace {

void require(bool ok, const char* name, double value, const char* range) {
    if (!ok) {
        throw std::invalid_argument(std::string(name) + " = " + std::to_string(value) + ": must be " + range);
    }
}

}  // namespace

Gains integer_gains(const Gains& g) {
    Gains out = g;
    out.kx = std::trunc(g.kx);
    out.ky = std::trunc(g.ky);
    out.kw = std::trunc(g.kw);
    return out;
}

void validate(const Gains& g) {
    require(g.kx >= 0.0 && g.kx <= 1000.0, "kx", g.kx, "in [0, 1000]");
    require(g.ky >= 0.0 && g.ky <= 1000.0, "ky", g.ky, "in [0, 1000]");
    require(g.kw >= 0.0 && g.kw <= 1000.0, "kw", g.kw, "in [0, 1000]");
    require(std::abs(g.vref_m_s) <= 10.0, "vref", g.vref_m_s, "in [-10, 10] m/s");
    require(std::abs(g.wref_rad_s) <= 100.0, "wref", g.wref_rad_s, "in [-100, 100] rad/s");
}

double lyapunov(const TrackingError<double>& e, double ky) {
    if (!(ky > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    return 0.5 * (e.x_m * e.x_m + e.y_m * e.y_m) + (1.0 - std::cos(e.theta_rad)) / ky;
}

double lyapunov_rate(const TrackingError<double>& e, const Gains& g) {
    if (!(g.ky > 0.0)) return std::numeric_limits<double>::quiet_NaN();
    const double s = std::sin(e.theta_rad);
    return -g.kx * e.x_m * e.x_m - g.vref_m_s * g.kw * s * s / g.ky;
}

}  // namespace ddmr::hostsim
