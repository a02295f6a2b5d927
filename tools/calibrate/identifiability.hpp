#pragma once
// What a log can tell about each fitted parameter (issue 18): the
// sensitivity of the predicted log (log_objective.hpp's predicted_log) to
// each parameter, by central differences at the fit, and what follows from it
// under the log's own noise, its quantisation (a uniform error over a 4 mm
// cell: sigma = 0.004 / sqrt(12) m per coordinate):
//
//   S_ij = d y_i / d ln(theta_j)      (the change of the log per relative change)
//   Fisher information F = S^T S / sigma^2, covariance C = F^-1 (of ln theta)
//   interval: theta_j x exp(+- 1.96 sqrt(C_jj))  (95 %, Gaussian, log scale)
//   correlation: C_jk / sqrt(C_jj C_kk)
//   singular values of S / sigma: a small one is a direction in parameter
//   space (its right singular vector) the log cannot see.
//
// The covariance comes from the SVD of S / sigma over the parameters the log
// depends on: C = V diag(1 / s^2) V^T over the directions it sees; a singular
// value below 1e-6 of the largest (or missing: fewer log values than
// parameters) is a direction it does not see.
//
// A parameter is refused as unidentifiable when the log does not depend on it
// (a 10 % change moves the whole log, root sum of squares over all its
// values, by less than one sigma), when it has weight (> 0.1) in a direction
// the log does not see, or when its interval is wider than a factor of 2
// either way; the message names the parameter it trades off with most.
//
// The same sigma is used for every value of the prediction, the two encoder
// totals (in metres of wheel travel) included: their own noise, about one
// edge (0.5 mm on the thesis robot), is smaller, so their weight is slightly
// understated.

#include <Eigen/Dense>

#include <functional>
#include <string>
#include <vector>

namespace ddmr::calibrate {

struct ParamIdentifiability {
    std::string key;
    double value = 0.0;
    double ci_lo = 0.0;     ///< 95 % interval (the value when it cannot be computed)
    double ci_hi = 0.0;
    double relative_sd = 0.0;    ///< sqrt(C_jj): the standard deviation of ln(theta) (inf when singular)
    double sensitivity_m = 0.0;  ///< RMS change of the predicted log for a +10 % change [m]
    bool identifiable = true;
    std::string reason;          ///< why not, in one sentence
};

struct Identifiability {
    std::vector<ParamIdentifiability> params;
    std::vector<double> singular_values;  ///< of S / sigma, largest first
    Eigen::MatrixXd correlation;          ///< parameters x parameters (NaN rows for a singular F)
    double sigma_m = 0.0;
};

/// The quantisation noise of one logged coordinate [m]: a uniform error over a 4 mm cell.
double log_noise_m();

/// `predict` maps the parameters' values to the predicted log; `keys` and
/// `at` (all > 0) name the fitted point. `relative_step` is the central
/// difference's step on ln(theta), (0, 0.5].
Identifiability analyse_identifiability(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                        const std::vector<std::string>& keys, const std::vector<double>& at,
                                        double sigma_m = log_noise_m(), double relative_step = 0.01);

}  // namespace ddmr::calibrate
