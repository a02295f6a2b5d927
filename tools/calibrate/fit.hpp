#pragma once
// The optimiser for calibrating the plant from a robot's logs (issue 18;
// the `ddmr-hil calibrate` command is being built on it): bounded, derivative-free
// minimisation of a loss over a few plant parameters with NLopt (Debian's
// libnlopt-cxx-dev): a seeded global stage, CRS2 with local mutation
// (NLOPT_GN_CRS2_LM: a population over the whole box), then a local polish
// from its best point with BOBYQA (NLOPT_LN_BOBYQA: quadratic models, few
// evaluations near a minimum). Each parameter is searched on [0, 1] scaled
// linearly between its bounds, so tolerances mean the same for an ohm and a
// volt. BOBYQA is restarted from its result while that still lowers the loss
// by 1e-4 of itself and its budget lasts.
//
// Deterministic: NLopt's generator is seeded from FitOptions::seed before
// each stage, and the evaluation order is NLopt's own (single thread). NLopt
// keeps that generator in a global: run one fit at a time per process.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace ddmr::calibrate {

struct FitParam {
    std::string key;     ///< for messages
    double start = 0.0;  ///< inside [lo, hi]
    double lo = 0.0;
    double hi = 0.0;     ///< > lo
};

struct FitOptions {
    uint64_t seed = 1;
    int global_evaluations = 200;  ///< CRS2 budget; 0: local stage only, from the starts
    int local_evaluations = 200;   ///< BOBYQA budget (its restarts included), >= 1
    double x_tolerance = 1e-4;     ///< relative to each parameter's box (scaled units)
    /// Called after every evaluation: (evaluations so far, best loss so far).
    std::function<void(int, double)> progress;
};

struct FitResult {
    std::vector<double> values;  ///< the best point, in the parameters' units
    double loss = 0.0;
    int evaluations = 0;
    double global_loss = 0.0;    ///< the best loss after the global stage (= the start's without one)
};

/// Throws std::invalid_argument naming the parameter: no parameters, a
/// search range that is empty or not finite (or, with `positive`, reaches 0
/// or below: a fit on the logarithm), a start outside its range. Both
/// stages (fit, fit_least_squares) check their box with it.
void check_search_box(const std::vector<FitParam>& params, bool positive);

/// Minimises `loss` (the parameters' values in their units -> a finite
/// number; a non-finite one counts as very bad) over the box. Throws
/// std::invalid_argument naming the parameter for a bad box or start.
FitResult fit(const std::vector<FitParam>& params, const std::function<double(const std::vector<double>&)>& loss,
              const FitOptions& options);

}  // namespace ddmr::calibrate
