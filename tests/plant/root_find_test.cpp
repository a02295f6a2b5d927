// Tests for plant/root_find: the safeguarded Newton behind every event and
// encoder-edge time. Roots worked out by hand.
#include "plant/root_find.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <utility>

namespace ddmr::plant {
namespace {

/// f(t) = e^{-1000 t} - 1/2, falling through 0 at t = ln 2 / 1000.
struct HalfLife {
    int* evaluations;
    std::pair<double, double> operator()(double t) const {
        ++*evaluations;
        const double e = std::exp(-1000.0 * t);
        return {e - 0.5, -1000.0 * e};
    }
};

TEST(RootFind, FindsTheRootOfAnExponentialToTheTolerance) {
    int n = 0;
    // ln 2 / 1000 = 6.931471805599453e-4 s.
    const double t = find_root(HalfLife{&n}, 0.0, 1e-3, 1.0);
    EXPECT_NEAR(t, 6.931471805599453e-4, kRootTolerance_s);
    EXPECT_GE(t, 0.0);
    EXPECT_LE(t, 1e-3);
}

TEST(RootFind, AGoodFirstGuessSavesEvaluations) {
    // Newton converges quadratically: from 1 ns off the root one step lands
    // within 1e-15 s, so the second evaluation ends it; from the end of the
    // bracket (0.31 ms off) it takes more.
    int from_end = 0;
    int from_guess = 0;
    const double a = find_root(HalfLife{&from_end}, 0.0, 1e-3, 1.0);
    const double b = find_root(HalfLife{&from_guess}, 0.0, 1e-3, 1.0, 6.931481805599453e-4);
    EXPECT_NEAR(a, b, kRootTolerance_s);
    EXPECT_LE(from_guess, 2);
    EXPECT_GT(from_end, from_guess);
}

TEST(RootFind, AFirstGuessOutsideTheBracketStartsFromItsEnd) {
    int outside = 0;
    int from_end = 0;
    const double a = find_root(HalfLife{&outside}, 0.0, 1e-3, 1.0, 5.0);
    const double b = find_root(HalfLife{&from_end}, 0.0, 1e-3, 1.0);
    EXPECT_EQ(a, b);
    EXPECT_EQ(outside, from_end);
    int nan_guess = 0;
    EXPECT_EQ(find_root(HalfLife{&nan_guess}, 0.0, 1e-3, 1.0, std::nan("")), b);
}

TEST(RootFind, StaysInTheBracketWhereNewtonWouldLeaveIt) {
    // f(t) = atan(t - 0.7) on [0, 10]: Newton from t = 10 jumps far outside
    // (to about -120); bisection takes over, and the root 0.7 is still found.
    auto f = [](double t) {
        const double u = t - 0.7;
        return std::pair<double, double>{std::atan(u), 1.0 / (1.0 + u * u)};
    };
    const double t = find_root(f, 0.0, 10.0, -1.0);
    EXPECT_NEAR(t, 0.7, 1e-12);
}

}  // namespace
}  // namespace ddmr::plant
