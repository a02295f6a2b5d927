// Trajectory metrics, checked on tracks small enough to work out by hand.
#include "comparison.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::test {
namespace {

using tools::Point2;

TEST(Comparison, MetricsOfAHandWorkedPair) {
    // Distances 0, 3 (3-4-5 offset... here straight 3 m in y) and 4:
    //   rms = sqrt((0 + 9 + 16) / 3) = sqrt(25 / 3) = 2.8868
    //   max = 4, endpoint = 4; reference end (3, 4) has norm 5: 80 %.
    const std::vector<Point2> a = {{0, 0}, {1, 3}, {3, 8}};
    const std::vector<Point2> ref = {{0, 0}, {1, 0}, {3, 4}};
    const auto m = tools::compare_tracks(a, ref);
    EXPECT_NEAR(m.rms_m, std::sqrt(25.0 / 3.0), 1e-12);
    EXPECT_DOUBLE_EQ(m.max_m, 4.0);
    EXPECT_DOUBLE_EQ(m.endpoint_m, 4.0);
    EXPECT_DOUBLE_EQ(m.endpoint_pct, 80.0);
    EXPECT_EQ(m.samples, 3u);
}

TEST(Comparison, IdenticalTracksAgreeExactly) {
    const std::vector<Point2> a = {{0.1, 0.2}, {0.3, -0.4}};
    const auto m = tools::compare_tracks(a, a);
    EXPECT_EQ(m.rms_m, 0.0);
    EXPECT_EQ(m.endpoint_pct, 0.0);
}

TEST(Comparison, MismatchedLengthsAreRefused) {
    EXPECT_THROW(tools::compare_tracks({{0, 0}}, {{0, 0}, {1, 1}}), std::invalid_argument);
    EXPECT_THROW(tools::compare_tracks({}, {}), std::invalid_argument);
}

TEST(Comparison, InterpolatesLinearlyAndClampsAtTheEnds) {
    const std::vector<double> t = {0.0, 1.0, 3.0};
    const std::vector<double> x = {0.0, 2.0, 2.0};
    const std::vector<double> y = {0.0, 0.0, 4.0};
    EXPECT_DOUBLE_EQ(tools::interpolate(t, x, y, 0.5).x_m, 1.0);
    EXPECT_DOUBLE_EQ(tools::interpolate(t, x, y, 2.0).y_m, 2.0);  // halfway from 1 s to 3 s
    EXPECT_DOUBLE_EQ(tools::interpolate(t, x, y, -1.0).x_m, 0.0);
    EXPECT_DOUBLE_EQ(tools::interpolate(t, x, y, 9.0).y_m, 4.0);
}

}  // namespace
}  // namespace ddmr::test
