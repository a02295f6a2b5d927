// Levenberg-Marquardt over ln(theta) on residuals whose minimum is known by
// construction: an exponential decay sampled without noise (both parameters
// come back), a minimum outside the box (held at the bound), the budget, and
// the one-line errors.
#include "calibrate/least_squares.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace ddmr::calibrate {
namespace {

/// y(t) = a exp(-t / tau) at t = 0, 0.1, ..., 2 minus the samples of a = 3, tau = 0.7.
std::vector<double> decay_residuals(const std::vector<double>& v) {
    std::vector<double> r;
    for (int k = 0; k <= 20; ++k) {
        const double t = 0.1 * k;
        r.push_back(v[0] * std::exp(-t / v[1]) - 3.0 * std::exp(-t / 0.7));
    }
    return r;
}

TEST(LeastSquares, RecoversAnExponentialDecay) {
    LeastSquaresOptions o;
    o.relative_step = 1e-4;  // smooth residuals: a small step is exact
    int calls = 0;
    o.progress = [&](int n, double) { calls = n; };
    const LeastSquaresResult r = fit_least_squares({{"a", 1.0, 0.1, 10.0}, {"tau", 2.0, 0.1, 10.0}}, decay_residuals, o);
    EXPECT_NEAR(r.values[0], 3.0, 1e-6);
    EXPECT_NEAR(r.values[1], 0.7, 1e-6);
    EXPECT_LT(r.sum_of_squares, 1e-12);
    EXPECT_LE(r.evaluations, o.max_evaluations);
    EXPECT_EQ(calls, r.evaluations);
    EXPECT_FALSE(r.stop.empty());
}

TEST(LeastSquares, AMinimumOutsideTheBoxIsHeldAtTheBound) {
    // The best a is 3; the box ends at 2: a stays at 2 and tau makes the best of it.
    const LeastSquaresResult r = fit_least_squares({{"a", 1.0, 0.1, 2.0}, {"tau", 0.7, 0.1, 10.0}}, decay_residuals, {});
    EXPECT_DOUBLE_EQ(r.values[0], 2.0);
    EXPECT_GT(r.values[1], 0.7);  // a longer decay makes up for the smaller start
}

TEST(LeastSquares, TheBudgetIsRespected) {
    LeastSquaresOptions o;
    o.max_evaluations = 7;
    const LeastSquaresResult r = fit_least_squares({{"a", 1.0, 0.1, 10.0}, {"tau", 2.0, 0.1, 10.0}}, decay_residuals, o);
    EXPECT_LE(r.evaluations, 7);
    EXPECT_EQ(r.stop, "the evaluation budget is spent");
}

TEST(LeastSquares, BadBoxesAndOptionsAreNamed) {
    try {
        (void)fit_least_squares({{"driver.drop_V", 1.0, 0.0, 2.0}}, decay_residuals, {});
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "driver.drop_V: the search range [0, 2] is empty, not finite or not positive");
    }
    EXPECT_THROW((void)fit_least_squares({{"a", 3.0, 0.5, 2.0}}, decay_residuals, {}), std::invalid_argument);
    LeastSquaresOptions o;
    o.relative_step = 0.0;
    EXPECT_THROW((void)fit_least_squares({{"a", 1.0, 0.5, 2.0}}, decay_residuals, o), std::invalid_argument);
    // Fewer residuals than parameters.
    const auto one = [](const std::vector<double>& v) { return std::vector<double>{v[0] - 1.0}; };
    EXPECT_THROW((void)fit_least_squares({{"a", 1.0, 0.5, 2.0}, {"b", 1.0, 0.5, 2.0}}, one, {}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::calibrate
