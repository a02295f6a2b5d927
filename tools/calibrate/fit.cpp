#include "calibrate/fit.hpp"

#include <fmt/format.h>
#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ddmr::calibrate {
namespace {

/// What NLopt sees for a loss that is not a number (a diverged plant).
constexpr double kNonFiniteLoss = 1e30;
/// A local restart is worth another when it lowered the loss by this fraction.
constexpr double kRestartGain = 1e-4;

struct Problem {
    const std::vector<FitParam>* params;
    const std::function<double(const std::vector<double>&)>* loss;
    const FitOptions* options;
    int evaluations = 0;
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> best_x;  ///< scaled

    std::vector<double> unscale(const std::vector<double>& z) const {
        std::vector<double> v(z.size());
        for (std::size_t i = 0; i < z.size(); ++i) {
            const FitParam& p = (*params)[i];
            v[i] = p.lo + std::clamp(z[i], 0.0, 1.0) * (p.hi - p.lo);
        }
        return v;
    }
};

double objective(const std::vector<double>& z, std::vector<double>& /*grad*/, void* data) {
    auto* pr = static_cast<Problem*>(data);
    double f = (*pr->loss)(pr->unscale(z));
    if (!std::isfinite(f)) f = kNonFiniteLoss;
    ++pr->evaluations;
    if (f < pr->best) {
        pr->best = f;
        pr->best_x = z;
    }
    if (pr->options->progress) pr->options->progress(pr->evaluations, pr->best);
    return f;
}

/// Runs one NLopt stage from z (scaled); the best point stays in the Problem.
void run_stage(nlopt::algorithm algorithm, int budget, std::vector<double> z, Problem& pr, uint64_t seed) {
    const std::size_t n = z.size();
    nlopt::opt opt(algorithm, static_cast<unsigned>(n));
    opt.set_lower_bounds(std::vector<double>(n, 0.0));
    opt.set_upper_bounds(std::vector<double>(n, 1.0));
    opt.set_min_objective(&objective, &pr);
    opt.set_maxeval(budget);
    opt.set_xtol_abs(pr.options->x_tolerance);
    nlopt::srand(static_cast<unsigned long>(seed));
    double f = 0.0;
    try {
        opt.optimize(z, f);
    } catch (const nlopt::roundoff_limited&) {
        // The best point so far is kept: a stage that cannot improve further is done.
    }
}

}  // namespace

void check_search_box(const std::vector<FitParam>& params, bool positive) {
    if (params.empty()) throw std::invalid_argument("calibrate: no parameter to fit");
    for (const FitParam& p : params) {
        if (!(std::isfinite(p.lo) && std::isfinite(p.hi) && p.lo < p.hi && (!positive || p.lo > 0.0))) {
            throw std::invalid_argument(fmt::format("{}: the search range [{}, {}] is {}", p.key, p.lo, p.hi,
                                                    positive ? "empty, not finite or not positive"
                                                             : "empty or not finite"));
        }
        if (!(p.start >= p.lo && p.start <= p.hi)) {
            throw std::invalid_argument(fmt::format("{}: the start {} is outside [{}, {}]", p.key, p.start, p.lo, p.hi));
        }
    }
}

FitResult fit(const std::vector<FitParam>& params, const std::function<double(const std::vector<double>&)>& loss,
              const FitOptions& options) {
    check_search_box(params, false);
    if (options.global_evaluations < 0 || options.local_evaluations < 1) {
        throw std::invalid_argument("calibrate: the global budget must be >= 0 and the local one >= 1");
    }
    Problem pr{&params, &loss, &options, 0, std::numeric_limits<double>::infinity(), {}};
    std::vector<double> z0(params.size());
    for (std::size_t i = 0; i < params.size(); ++i) z0[i] = (params[i].start - params[i].lo) / (params[i].hi - params[i].lo);

    FitResult r;
    if (options.global_evaluations > 0) {
        run_stage(nlopt::GN_CRS2_LM, options.global_evaluations, z0, pr, options.seed);
    } else {
        std::vector<double> unused;
        objective(z0, unused, &pr);
    }
    r.global_loss = pr.best;
    // BOBYQA, restarted from its result while a restart still improves it
    // (a restart rebuilds the quadratic model with a fresh trust region: the
    // loss is only piecewise smooth, encoder edges being discrete, and one
    // run can stop on a kink), within the local budget.
    const int local_start = pr.evaluations;
    uint64_t stage_seed = options.seed + 1;
    for (bool first = true;; first = false) {
        const int left = options.local_evaluations - (pr.evaluations - local_start);
        // A restart's first model needs 2n + 1 points to be of any use.
        if (left < 1 || (!first && left < 2 * static_cast<int>(params.size()) + 2)) break;
        const double before = pr.best;
        run_stage(nlopt::LN_BOBYQA, left, pr.best_x, pr, stage_seed++);
        if (!(pr.best < before - kRestartGain * std::max(std::fabs(before), 1e-12))) break;
    }
    r.values = pr.unscale(pr.best_x);
    r.loss = pr.best;
    r.evaluations = pr.evaluations;
    return r;
}

}  // namespace ddmr::calibrate
