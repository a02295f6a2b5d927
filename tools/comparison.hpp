#pragma once
// Trajectory comparison on the EEPROM log's time base: one point per logged
// sample (every 10 control iterations), for three sources of the robot's
// position: the firmware's log, the HIL plant's truth, and the host
// simulation. The metrics are those of the thesis (ch. 7): an endpoint error
// relative to the length of the end vector (3.7 % on the 0.6 m circle).

#include <string>
#include <vector>

#include "hostsim/host_sim.hpp"

namespace ddmr::tools {

struct Point2 {
    double x_m = 0.0;
    double y_m = 0.0;
};

struct PairMetrics {
    double rms_m = 0.0;       ///< root mean square distance over the samples
    double max_m = 0.0;       ///< largest distance
    double endpoint_m = 0.0;  ///< distance at the last sample
    /// endpoint_m over the norm of the reference's end vector (its last point
    /// seen from the start at the origin), in percent.
    double endpoint_pct = 0.0;
    std::size_t samples = 0;
};

/// Compares `a` with `reference`, sample by sample (same length, >= 1; throws
/// std::invalid_argument otherwise).
PairMetrics compare_tracks(const std::vector<Point2>& a, const std::vector<Point2>& reference);

/// Linear interpolation of (t, x, y) samples at time t (clamped to the ends).
/// `t_s` must be non-decreasing.
Point2 interpolate(const std::vector<double>& t_s, const std::vector<double>& x_m,
                   const std::vector<double>& y_m, double t);

/// The sketch writes one EEPROM log sample every 10 control iterations.
inline constexpr int kIterationsPerLogSample = 10;

/// The simulation's true position after 10 (k + 1) control periods, k <
/// `samples`: the simulated counterpart of the EEPROM log's samples.
std::vector<Point2> sim_track(const hostsim::SimResult& r, const hostsim::SimConfig& c, std::size_t samples);

}  // namespace ddmr::tools
