#include "comparison.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ddmr::tools {

PairMetrics compare_tracks(const std::vector<Point2>& a, const std::vector<Point2>& reference) {
    if (a.empty() || a.size() != reference.size()) {
        throw std::invalid_argument("compare_tracks: " + std::to_string(a.size()) + " vs " +
                                    std::to_string(reference.size()) + " samples");
    }
    PairMetrics m;
    m.samples = a.size();
    double sum_sq = 0.0;
    for (std::size_t k = 0; k < a.size(); ++k) {
        const double d = std::hypot(a[k].x_m - reference[k].x_m, a[k].y_m - reference[k].y_m);
        sum_sq += d * d;
        m.max_m = std::max(m.max_m, d);
    }
    m.rms_m = std::sqrt(sum_sq / static_cast<double>(a.size()));
    m.endpoint_m = std::hypot(a.back().x_m - reference.back().x_m, a.back().y_m - reference.back().y_m);
    const double end_norm = std::hypot(reference.back().x_m, reference.back().y_m);
    m.endpoint_pct = end_norm > 0.0 ? 100.0 * m.endpoint_m / end_norm : 0.0;
    return m;
}

Point2 interpolate(const std::vector<double>& t_s, const std::vector<double>& x_m,
                   const std::vector<double>& y_m, double t) {
    if (t_s.empty()) throw std::invalid_argument("interpolate: no samples");
    if (t <= t_s.front()) return {x_m.front(), y_m.front()};
    if (t >= t_s.back()) return {x_m.back(), y_m.back()};
    const auto it = std::upper_bound(t_s.begin(), t_s.end(), t);
    const auto i = static_cast<std::size_t>(it - t_s.begin());
    const double t0 = t_s[i - 1];
    const double t1 = t_s[i];
    const double f = t1 > t0 ? (t - t0) / (t1 - t0) : 0.0;
    return {x_m[i - 1] + f * (x_m[i] - x_m[i - 1]), y_m[i - 1] + f * (y_m[i] - y_m[i - 1])};
}

std::vector<Point2> sim_track(const hostsim::SimResult& r, const hostsim::SimConfig& c, std::size_t samples) {
    std::vector<double> t, x, y;
    for (const auto& s : r.samples) {
        t.push_back(s.t_s);
        x.push_back(s.x_m);
        y.push_back(s.y_m);
    }
    std::vector<Point2> out;
    for (std::size_t k = 0; k < samples; ++k) {
        out.push_back(interpolate(t, x, y, static_cast<double>(kIterationsPerLogSample * (k + 1)) * c.period_s));
    }
    return out;
}

}  // namespace ddmr::tools
