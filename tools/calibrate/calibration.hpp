#pragma once
// A calibration from end to end (issue 18), what `ddmr-hil calibrate` runs:
// the logs split into the fitted part and the judged part, the parameters to
// fit (given, or chosen by what the logs can pin down), the fit
// (log_objective.hpp's loss averaged over the fitted logs, fit.hpp's
// optimiser), the identifiability at the fitted point (intervals,
// correlations), and the distances to every log before and after.
//
// Each log is a run of the same case (the objective's base configuration).
// A parameter is searched between start / range_factor and
// start x range_factor, inside its valid range. The fit is two stages: least
// squares on the cells' centres (least_squares.hpp: Levenberg-Marquardt, a
// few Jacobians), then the robust loss (fit.hpp) from its result.
// A motor's torque constant follows its back-EMF constant (the same ratio to
// the start) unless it is fitted itself: in SI units the two are one
// constant of the motor.

#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "calibrate/fit.hpp"
#include "calibrate/identifiability.hpp"
#include "calibrate/least_squares.hpp"
#include "calibrate/log_objective.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::calibrate {

/// The plant parameters a calibration considers when it is not told which:
/// those of the motors, the driver and the battery that a closed-loop log
/// can show (not the inductance, the gear ratio, the encoders or the
/// kinematics: see docs/calibration.md).
const std::vector<std::string>& default_candidate_keys();

inline FitOptions polish_options() {
    FitOptions o;
    o.global_evaluations = 0;
    o.local_evaluations = 60;
    return o;
}

/// The keys that follow `key` when it is fitted and they are not (the
/// motor's torque constant follows its back-EMF constant).
std::vector<std::string> param_keys_tied_to(const std::string& key);

/// The fitted key that `key` follows, or "" (it is fitted itself, or follows none).
std::string tied_to(const std::string& key, const std::vector<std::string>& fitted);

struct CalibrationSetup {
    std::vector<RobotLog> logs;          ///< fitted (their first `split` fraction with a split)
    std::vector<RobotLog> holdout_logs;  ///< judged, never fitted
    /// In (0, 1): each log's first fraction of the samples is fitted, the rest judged.
    std::optional<double> split;
    plant::RobotParams start = plant::default_robot_params();
    /// The parameters to fit (file keys); empty: chosen among
    /// default_candidate_keys() by what the fitted logs pin down.
    std::vector<std::string> keys;
    ObjectiveConfig objective;
    LeastSquaresOptions least_squares;
    /// The robust loss's stage from the least squares' result: no global
    /// search by default, a short BOBYQA polish.
    FitOptions fit = polish_options();
    double range_factor = 2.0;      ///< > 1
    /// A default key is kept when its interval is within x exp(this) either way.
    double max_half_width = 0.15;
    /// How well the host model predicts the HIL on the same plant [m RMS]
    /// (measured: 0.3-0.5 mm on case 1): values it predicts to within this
    /// are not told apart (identifiability.hpp's model tolerance).
    double model_tolerance_m = 1e-3;
    /// One line per stage ("choosing the parameters: ..."), for stderr.
    std::function<void(const std::string&)> stage;
};

/// The distances of one plant to one set of logs (log_objective's metrics).
struct SetScore {
    struct PerLog {
        std::string source;
        TrackMetrics metrics;
        bool totals = false;                   ///< the run reaches the log's end: the totals are compared
        uint64_t logged_count1 = 0, logged_count2 = 0;
    };
    std::vector<PerLog> logs;
    double rms_m = 0.0;        ///< over every counted sample of the set
    double max_m = 0.0;
    double endpoint_m = 0.0;   ///< mean over the logs
    double endpoint_pct = 0.0; ///< mean over the logs
    std::size_t samples = 0;
};

struct FittedParam {
    std::string key;
    const char* unit = "";
    double start = 0.0, lo = 0.0, hi = 0.0;  ///< the start and the search box
    double value = 0.0;
    ParamIdentifiability at_fit;             ///< its interval and whether the fit pins it
};

struct CalibrationResult {
    std::vector<FittedParam> params;
    /// The candidates left out of a default choice, with their reasons.
    std::vector<std::pair<std::string, std::string>> not_fitted;
    Identifiability identifiability;  ///< at the fitted point, over the fitted parameters
    LeastSquaresResult least_squares;
    FitResult fit;                    ///< the robust stage: its values are the result
    plant::RobotParams fitted;
    std::vector<LogRun> train, holdout;
    SetScore before_train, after_train;
    std::optional<SetScore> before_holdout, after_holdout;  ///< when something is held out
    /// RMS of the fitted plant's least-squares residuals (distances to the
    /// cells' centres) [m]; the intervals assume max(this, the quantisation's sigma).
    double residual_rms_m = 0.0;
    /// What a user should know about the fit, one sentence each (the logs'
    /// own warnings, a spent budget, a value at its search bound, a residual
    /// above the quantisation).
    std::vector<std::string> warnings;
};

/// A --fit key the logs cannot see (what() names it and says why, one line).
class UnidentifiableParameter : public std::invalid_argument {
  public:
    using std::invalid_argument::invalid_argument;
};

/// The fitted and judged runs of the setup's logs (the split applied).
/// Throws std::invalid_argument for no log, a split outside (0, 1) or one
/// that leaves either part empty.
void make_runs(const CalibrationSetup& setup, std::vector<LogRun>& train, std::vector<LogRun>& holdout);

/// The distances of `params` to `runs`.
SetScore score(const plant::RobotParams& params, const std::vector<LogRun>& runs, const ObjectiveConfig& objective);

/// Runs the calibration. Throws std::invalid_argument for an unknown key, a
/// key that is not a real-valued parameter or is 0 in the start plant, a bad
/// split or box; UnidentifiableParameter for a given key the logs cannot see
/// at the start; std::runtime_error when no default candidate is pinned down.
CalibrationResult calibrate(const CalibrationSetup& setup);

}  // namespace ddmr::calibrate
