#pragma once
// How well a plant reproduces a logged run (issue 18): the closed loop is
// re-simulated with the host simulation's firmware model (tools/hostsim:
// the sketch's gains, float arithmetic, encoder odometry, loop period,
// feed-forward constants and PWM quantisation) on the candidate plant, and
// each logged sample is compared with the controller's pose the simulation
// logs at the same iteration, as the distance to the sample's cell
// (log_residual.hpp). The encoder totals (Count1, Count2) are compared at
// the run's end, in metres of wheel travel of the base plant (a fixed scale:
// a candidate's wheel radius does not change what a count is worth here).
//
// The encoders' magnets sit at an unknown angle when the robot starts: the
// simulation is run once per initial phase in `encoder_phases` and the loss
// and metrics are averaged over them, so a fit does not tune the phase.
//
// loss = mean over phases of
//        [ sum over counted samples and both axes of soft_l1(cell distance, scale)
//          + count_weight x sum over both totals of soft_l1(total error [m], scale) ]
//        / (2 x counted samples + 2 x count_weight when the totals count)

#include <cstddef>
#include <cstdint>
#include <vector>

#include "calibrate/robot_log.hpp"
#include "tools/hostsim/host_sim.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::calibrate {

/// A logged run and the part of it that counts.
struct LogRun {
    RobotLog log;
    std::size_t first = 0;  ///< samples [first, end) count
    std::size_t end = 0;    ///< 0: to the last sample; the totals count only when the samples reach it
};

struct ObjectiveConfig {
    /// The simulation: case, gains, PWM model and loop period. Its plant is
    /// replaced by the candidate's; its fidelity by the firmware model
    /// without eeprom_bytes (the objective takes the unquantised pose).
    hostsim::SimConfig base = hostsim::config_for_case(1, hostsim::Model::firmware);
    std::vector<double> encoder_phases{0.125, 0.375, 0.625, 0.875};  ///< each in [0, 1)
    double loss_scale_m = 0.004;  ///< soft-L1 scale: one log count
    double count_weight = 1.0;    ///< weight of each total against one sample axis, >= 0
    /// Threads the phases' simulations run on (0: one per core); the result
    /// does not depend on it.
    int threads = 0;
};

/// Distances between the simulation and the log over the counted samples,
/// averaged over the encoder phases.
struct TrackMetrics {
    double rms_m = 0.0;       ///< RMS of the per-sample distance to the cells (hypot of both axes)
    double max_m = 0.0;
    double endpoint_m = 0.0;  ///< at the last counted sample
    /// endpoint_m over the length of the logged end vector (the last counted
    /// sample decoded, seen from the origin), in percent: the thesis's metric.
    double endpoint_pct = 0.0;
    std::size_t samples = 0;
    double count1 = 0.0;      ///< the simulation's encoder totals (mean over phases)
    double count2 = 0.0;
};

struct Evaluation {
    double loss = 0.0;
    TrackMetrics metrics;
    bool plant_failed = false;  ///< a simulation stopped early (its loss is large, not NaN)
};

/// Throws std::invalid_argument naming the problem for an empty sample
/// range, a phase outside [0, 1), a non-positive scale or a negative weight.
void validate(const LogRun& run, const ObjectiveConfig& config);

/// Evaluates `params` against `run`. Deterministic.
Evaluation evaluate(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config);

/// The simulation's counterpart of the counted log, averaged over the
/// encoder phases: x then y [m] of each counted sample's controller pose
/// (unquantised), then, when the totals count, the two encoder totals in
/// metres of wheel travel. What the identifiability analysis differentiates.
std::vector<double> predicted_log(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config);

/// What a least-squares fit drives to zero: predicted_log's values minus
/// the log's, each coordinate from the centre of its sample's nearest cell
/// (log_residual.hpp), each total in metres of wheel travel. Same order and
/// size as predicted_log.
std::vector<double> centre_residuals(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config);

/// The logged position of sample k [m]: the bytes unwrapped from sample 0
/// (hil::unwrap_counts) over 250.
std::vector<std::pair<double, double>> logged_positions(const RobotLog& log);

}  // namespace ddmr::calibrate
