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
// A parameter is refused as unidentifiable when the log does not depend on it
// (its column of S is below one sigma for a 10 % change) or when its
// interval is wider than a factor of 2 either way (the data cannot pin it,
// alone or through a trade-off with the others: the message names the
// parameter it trades off with most).

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
