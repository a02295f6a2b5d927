#include "plant/reflectance_sensor.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "plant/units.hpp"

namespace ddmr::plant {

namespace {

/// The spot's sample directions: every 90 degrees at half the radius, then
/// every 45 degrees on the rim (unit vectors, computed once).
struct SpotDirections {
    std::array<Eigen::Vector2d, 4> inner;
    std::array<Eigen::Vector2d, 8> rim;
    SpotDirections() {
        for (int k = 0; k < 4; ++k) {
            const double a = k * kPi / 2.0;
            inner[static_cast<std::size_t>(k)] = Eigen::Vector2d(std::cos(a), std::sin(a));
        }
        for (int k = 0; k < 8; ++k) {
            const double a = k * kPi / 4.0;
            rim[static_cast<std::size_t>(k)] = Eigen::Vector2d(std::cos(a), std::sin(a));
        }
    }
};

}  // namespace

double spot_reflectance(const World& world, const Eigen::Vector2d& p, double spot_diameter_m) {
    if (spot_diameter_m <= 0.0) return reflectance_at(world, p);
    static const SpotDirections directions;
    const double r = spot_diameter_m / 2.0;
    if (clear_of_lines(world, p, r)) {
        // All 13 points read the floor: the same sum, without the geometry.
        double floor = world.floor_reflectance;
        for (int k = 0; k < 12; ++k) floor += world.floor_reflectance;
        return floor / 13.0;
    }
    double sum = reflectance_at(world, p);
    for (const Eigen::Vector2d& d : directions.inner) sum += reflectance_at(world, p + 0.5 * r * d);
    for (const Eigen::Vector2d& d : directions.rim) sum += reflectance_at(world, p + r * d);
    return sum / 13.0;
}

double analog_output_v(const AnalogReflectanceParams& p, double reflectance) {
    const double slope = (p.black_v - p.white_v) / (kBlackTapeReflectance - kWhiteReflectance);
    const double v = p.white_v + slope * (reflectance - kWhiteReflectance);
    return std::clamp(v, 0.0, p.supply_v);
}

double rc_decay_s(const RcReflectanceParams& p, double reflectance) {
    // 1/t = g0 + g1 r through (white, 1/white_decay) and (black, 1/black_decay).
    const double g1 = (1.0 / p.white_decay_s - 1.0 / p.black_decay_s) / (kWhiteReflectance - kBlackTapeReflectance);
    const double g0 = 1.0 / p.black_decay_s - g1 * kBlackTapeReflectance;
    return 1.0 / (g0 + g1 * std::max(reflectance, kBlackTapeReflectance));
}

}  // namespace ddmr::plant
