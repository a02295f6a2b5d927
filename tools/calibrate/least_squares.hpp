#pragma once
// The least-squares stage of a calibration (issue 18): Levenberg-Marquardt
// (Eigen's unsupported LevenbergMarquardt module, MINPACK's lmder) on
// residuals that are smooth in the parameters (log_objective.hpp's
// centre_residuals), over ln(theta): each parameter is positive and a step
// means the same relative change for an ohm and a volt. The Jacobian is
// taken by central differences of a fixed relative step (5 % by default):
// the simulated log moves in small jumps (encoder edges are discrete), and a
// step much smaller than 5 % sees the jumps, not the slope. A parameter is
// held inside its box [lo, hi] (its value clamped there).
//
// Gauss-Newton converges in a few Jacobians where a derivative-free search
// needs hundreds of evaluations: on a five-parameter closed-loop fit it is
// what makes a calibration take a minute.

#include <functional>
#include <string>
#include <vector>

#include "calibrate/fit.hpp"

namespace ddmr::calibrate {

struct LeastSquaresOptions {
    int max_evaluations = 300;     ///< residual evaluations, Jacobians' included, >= 1
    double relative_step = 0.05;   ///< of the central differences on ln(theta), (0, 0.5]
    double tolerance = 1e-6;       ///< relative change of the parameters or of the cost that ends it
    /// Called after every evaluation: (evaluations so far, best sum of squares so far).
    std::function<void(int, double)> progress;
};

struct LeastSquaresResult {
    std::vector<double> values;  ///< the best point seen
    double sum_of_squares = 0.0; ///< there
    int evaluations = 0;
    std::string stop;            ///< why it stopped, for the record
};

/// Minimises the sum of squares of `residuals` (fixed length) over the box,
/// from each parameter's start. Every lo must be > 0. Throws
/// std::invalid_argument naming a parameter for a bad box or start.
LeastSquaresResult fit_least_squares(const std::vector<FitParam>& params,
                                     const std::function<std::vector<double>(const std::vector<double>&)>& residuals,
                                     const LeastSquaresOptions& options);

}  // namespace ddmr::calibrate
