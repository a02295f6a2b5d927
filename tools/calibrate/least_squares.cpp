#include "calibrate/least_squares.hpp"

#include <fmt/format.h>
#include <unsupported/Eigen/LevenbergMarquardt>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>
#include <stdexcept>

namespace ddmr::calibrate {
namespace {

/// A residual this large stands for a value that is not a number (a diverged plant).
constexpr double kNonFiniteResidual = 1e3;

/// The parameters' values at z = ln(value), clamped into their box.
std::vector<double> values_at(const std::vector<FitParam>& params, const Eigen::VectorXd& z) {
    std::vector<double> v(static_cast<std::size_t>(z.size()));
    for (std::size_t i = 0; i < v.size(); ++i) {
        v[i] = std::clamp(std::exp(z(static_cast<Eigen::Index>(i))), params[i].lo, params[i].hi);
    }
    return v;
}

struct Problem : Eigen::DenseFunctor<double> {
    const std::vector<FitParam>* params;
    const std::function<std::vector<double>(const std::vector<double>&)>* residuals;
    const LeastSquaresOptions* options;
    int evaluations = 0;
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> best_values;

    Problem(int n, int m, const std::vector<FitParam>* p,
            const std::function<std::vector<double>(const std::vector<double>&)>* r, const LeastSquaresOptions* o)
        : DenseFunctor<double>(n, m), params(p), residuals(r), options(o) {}

    std::vector<double> values_of(const InputType& z) const { return values_at(*params, z); }

    /// The residuals at the start, evaluated (and counted) before the
    /// minimiser to learn their number: its own first evaluation, there, reuses them.
    std::optional<std::pair<InputType, std::vector<double>>> start;

    /// One evaluation; false when the budget is spent.
    bool eval(const InputType& z, ValueType& f) {
        const bool at_start = start && start->first == z;
        if (!at_start && evaluations >= options->max_evaluations) return false;
        const std::vector<double> v = values_of(z);
        const std::vector<double> r = at_start ? start->second : (*residuals)(v);
        if (at_start) {
            start.reset();
            --evaluations;  // counted once, before the minimiser
        }
        if (static_cast<int>(r.size()) != values()) throw std::runtime_error("least squares: the residuals changed size");
        f.resize(values());
        double ss = 0.0;
        for (std::size_t i = 0; i < r.size(); ++i) {
            const double x = std::isfinite(r[i]) ? r[i] : kNonFiniteResidual;
            f(static_cast<Eigen::Index>(i)) = x;
            ss += x * x;
        }
        ++evaluations;
        if (ss < best) {
            best = ss;
            best_values = v;
        }
        if (options->progress) options->progress(evaluations, best);
        return true;
    }

    int operator()(const InputType& z, ValueType& f) { return eval(z, f) ? 0 : -1; }

    int df(const InputType& z_in, JacobianType& j) {
        const double h = options->relative_step;
        j.resize(values(), inputs());
        // Around the point as evaluated (clamped into the box): beyond a
        // bound the residuals do not change, and a zero column would keep
        // the parameter out there.
        InputType z = z_in;
        for (Eigen::Index c = 0; c < inputs(); ++c) {
            const FitParam& p = (*params)[static_cast<std::size_t>(c)];
            z(c) = std::clamp(z(c), std::log(p.lo), std::log(p.hi));
        }
        ValueType up, down;
        for (Eigen::Index c = 0; c < inputs(); ++c) {
            InputType zu = z;
            InputType zd = z;
            zu(c) += h;
            zd(c) -= h;
            if (!eval(zu, up) || !eval(zd, down)) return -1;
            j.col(c) = (up - down) / (2.0 * h);
        }
        return 0;
    }
};

const char* status_text(Eigen::LevenbergMarquardtSpace::Status s) {
    using namespace Eigen::LevenbergMarquardtSpace;
    switch (s) {
        case RelativeReductionTooSmall: return "the cost stopped falling";
        case RelativeErrorTooSmall: return "the parameters stopped moving";
        case RelativeErrorAndReductionTooSmall: return "the cost and the parameters stopped changing";
        case CosinusTooSmall: return "the residuals are orthogonal to the Jacobian (a minimum)";
        case TooManyFunctionEvaluation: return "the evaluation budget is spent";
        case FtolTooSmall:
        case XtolTooSmall:
        case GtolTooSmall: return "no further progress is possible at machine precision";
        case UserAsked: return "the evaluation budget is spent";
        default: return "stopped";
    }
}

}  // namespace

LeastSquaresResult fit_least_squares(const std::vector<FitParam>& params,
                                     const std::function<std::vector<double>(const std::vector<double>&)>& residuals,
                                     const LeastSquaresOptions& options) {
    check_search_box(params, /*positive=*/true);  // the fit runs on ln(value)
    if (options.max_evaluations < 1) throw std::invalid_argument("calibrate: the least-squares budget must be >= 1");
    if (!(options.relative_step > 0.0 && options.relative_step <= 0.5)) {
        throw std::invalid_argument("calibrate: the least-squares step must be in (0, 0.5]");
    }
    const auto n = static_cast<int>(params.size());
    Eigen::VectorXd z(n);
    for (int i = 0; i < n; ++i) z(i) = std::log(params[static_cast<std::size_t>(i)].start);
    // The number of residuals, from one evaluation at the start (counted).
    std::vector<double> start_values;
    start_values.reserve(params.size());
    for (const FitParam& p : params) start_values.push_back(p.start);
    std::vector<double> start_residuals = residuals(values_at(params, z));  // where the minimiser starts
    const int m = static_cast<int>(start_residuals.size());
    if (m < n) throw std::invalid_argument(fmt::format("calibrate: {} residuals cannot fit {} parameters", m, n));
    Problem problem(n, m, &params, &residuals, &options);
    problem.evaluations = 1;
    problem.start.emplace(z, std::move(start_residuals));
    Eigen::LevenbergMarquardt<Problem> lm(problem);
    lm.setXtol(options.tolerance);
    lm.setFtol(options.tolerance);
    lm.setMaxfev(options.max_evaluations);
    const Eigen::LevenbergMarquardtSpace::Status status = lm.minimize(z);
    LeastSquaresResult r;
    r.values = problem.best_values.empty() ? start_values : problem.best_values;
    r.sum_of_squares = problem.best;
    r.evaluations = problem.evaluations;
    r.stop = status_text(status);
    return r;
}

}  // namespace ddmr::calibrate
