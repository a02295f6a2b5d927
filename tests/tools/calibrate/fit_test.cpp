// The optimiser on losses whose minimum is known by construction (its use on
// a synthetic robot's logs: calibration_test.cpp).
#include "calibrate/fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>


namespace ddmr::calibrate {
namespace {

double bowl(const std::vector<double>& v) {
    // Minimum 0 at (1.3, -0.4); the second axis 10 times stiffer.
    return (v[0] - 1.3) * (v[0] - 1.3) + 10.0 * (v[1] + 0.4) * (v[1] + 0.4);
}

const std::vector<FitParam> kBox = {{"a", 0.5, 0.0, 3.0}, {"b", 0.5, -1.0, 1.0}};

TEST(Fit, FindsTheMinimumOfABowl) {
    const FitResult r = fit(kBox, bowl, FitOptions{});
    ASSERT_EQ(r.values.size(), 2u);
    EXPECT_NEAR(r.values[0], 1.3, 1e-3);
    EXPECT_NEAR(r.values[1], -0.4, 1e-3);
    EXPECT_LT(r.loss, 1e-6);
    EXPECT_LE(r.loss, r.global_loss);
    EXPECT_LE(r.evaluations, 400);
}

TEST(Fit, OneParameterAndALocalStageOnly) {
    FitOptions o;
    o.global_evaluations = 0;
    const FitResult r = fit({{"R", 5.0, 4.0, 8.0}}, [](const std::vector<double>& v) { return std::fabs(v[0] - 6.2); }, o);
    EXPECT_NEAR(r.values[0], 6.2, 1e-3);
}

TEST(Fit, TheSameSeedGivesTheSameFitAndProgressIsReported) {
    FitOptions o;
    int calls = 0;
    double last_best = std::numeric_limits<double>::infinity();
    bool in_order = true;
    o.progress = [&](int n, double best) {
        ++calls;
        in_order = in_order && best <= last_best && n == calls;  // counted from 1, the best never rises
        last_best = best;
    };
    const FitResult a = fit(kBox, bowl, o);
    EXPECT_EQ(calls, a.evaluations);
    EXPECT_TRUE(in_order);
    calls = 0;
    last_best = std::numeric_limits<double>::infinity();
    const FitResult b = fit(kBox, bowl, o);
    EXPECT_EQ(a.values, b.values);
    EXPECT_EQ(a.evaluations, b.evaluations);
    EXPECT_TRUE(in_order);
    o.seed = 2;  // another seed: another path (the same minimum)
    const FitResult c = fit(kBox, bowl, o);
    EXPECT_NEAR(c.values[0], 1.3, 1e-3);
}

TEST(Fit, ANonFiniteLossIsAvoidedNotFatal) {
    // NaN on half of the box: the minimum on the other half is found.
    const auto f = [](const std::vector<double>& v) {
        return v[0] > 2.0 ? std::numeric_limits<double>::quiet_NaN() : (v[0] - 1.0) * (v[0] - 1.0) + v[1] * v[1];
    };
    const FitResult r = fit(kBox, f, FitOptions{});
    EXPECT_NEAR(r.values[0], 1.0, 1e-3);
    EXPECT_NEAR(r.values[1], 0.0, 1e-3);
}

TEST(Fit, ABadBoxOrStartIsNamed) {
    const auto f = [](const std::vector<double>&) { return 0.0; };
    try {
        fit({{"motor1.resistance_ohm", 5.0, 6.0, 6.0}}, f, FitOptions{});
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "motor1.resistance_ohm: the search range [6, 6] is empty or not finite");
    }
    try {
        fit({{"driver.drop_V", 3.0, 0.5, 2.5}}, f, FitOptions{});
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "driver.drop_V: the start 3 is outside [0.5, 2.5]");
    }
    EXPECT_THROW(fit({}, f, FitOptions{}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::calibrate
