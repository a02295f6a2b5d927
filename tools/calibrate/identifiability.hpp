#pragma once
// What a log can tell about each fitted parameter (issue 18): the
// sensitivity of the predicted log (log_objective.hpp's predicted_log) to
// each parameter, by central differences at the fit, and what follows from it
// under the log's own noise, its quantisation (a uniform error over a 4 mm
// cell: sigma = 0.004 / sqrt(12) m per coordinate):
//
//   S_ij = d y_i / d ln(theta_j)      (the change of the log per relative change)
//   Fisher information F = S^T S / sigma^2, covariance C = F^-1 (of ln theta)
//   interval: theta_j x exp(+- h_j), h_j = max(1.96 sqrt(C_jj), t sqrt(rows) sqrt(C_jj) / sigma)
//     the first: 95 %, Gaussian, log scale, under the quantisation noise alone;
//     the second: the change (the others re-fitted, linearised) that moves the
//     predicted log by t RMS, t the model's own tolerance (model_tolerance_m,
//     0 by default): a model that is right only to t cannot tell values apart
//     that it predicts to within t, however many samples there are.
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
// either way (h_j > ln 2); the message names the parameter it trades off with most.
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
    /// Of the interval on ln(theta): max(1.96 relative_sd, the model
    /// tolerance's) (inf when singular).
    double half_width = 0.0;
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

/// S = d predict / d ln(theta) at `at` by central differences of step
/// `relative_step` on ln(theta), (0, 0.5]: one column per parameter.
Eigen::MatrixXd sensitivity_matrix(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                   const std::vector<double>& at, double relative_step = 0.01);

/// The analysis of a sensitivity matrix S (one column per key) at `at`.
Identifiability analyse_sensitivities(const Eigen::MatrixXd& s, const std::vector<std::string>& keys,
                                      const std::vector<double>& at, double sigma_m = log_noise_m(),
                                      double model_tolerance_m = 0.0);

/// Which of the candidate parameters (columns of S) a fit can pin down
/// together, chosen greedily: the most visible first (the largest column of
/// S), each kept when, with those kept before it, it is identifiable, its
/// interval's half-width on ln(theta) is at most `max_half_width` and it
/// spoils none kept before. What is not kept has its reason.
struct Selection {
    std::vector<std::size_t> chosen;  ///< column indices, ascending
    struct LeftOut {
        std::size_t index = 0;
        std::string reason;
    };
    std::vector<LeftOut> left_out;    ///< in the order they were tried
};
Selection select_identifiable(const Eigen::MatrixXd& s, const std::vector<std::string>& keys,
                              const std::vector<double>& at, double max_half_width, double sigma_m = log_noise_m(),
                              double model_tolerance_m = 0.0);

/// `predict` maps the parameters' values to the predicted log; `keys` and
/// `at` (all > 0) name the fitted point. `relative_step` is the central
/// difference's step on ln(theta), (0, 0.5].
Identifiability analyse_identifiability(const std::function<std::vector<double>(const std::vector<double>&)>& predict,
                                        const std::vector<std::string>& keys, const std::vector<double>& at,
                                        double sigma_m = log_noise_m(), double relative_step = 0.01,
                                        double model_tolerance_m = 0.0);

}  // namespace ddmr::calibrate
