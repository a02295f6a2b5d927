// Reflectance sensors' outputs, each number worked out by hand from
// plant/reflectance_sensor.hpp and ../shared/SENSORS.md section 2.
#include "plant/reflectance_sensor.hpp"
#include "plant/units.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::plant {
namespace {

/// A 19 mm black tape along the x axis (edges at y = +-9.5 mm).
World tape_along_x() {
    World w;
    FloorLine l;
    l.pieces = {LinePiece::segment({-1.0, 0.0}, {1.0, 0.0})};
    w.lines.push_back(l);
    return w;
}

TEST(SpotReflectance, IsTheFloorsOnAPlainFloorAndTheTapesInsideIt) {
    const World w = tape_along_x();
    EXPECT_DOUBLE_EQ(spot_reflectance(w, {0.0, 0.05}, 0.003), kWhiteReflectance);
    EXPECT_DOUBLE_EQ(spot_reflectance(w, {0.0, 0.0}, 0.003), kBlackTapeReflectance);  // all 13 points on the tape
}

TEST(SpotReflectance, AveragesThirteenPointsAcrossAnEdge) {
    // A 3 mm spot 0.1 mm inside the edge at y = 9.5 mm: the points above its
    // centre (half radius at 90 deg, rim at 45, 90, 135 deg: 4 points) are on
    // the white floor, the other 9 on the tape: (9 x 0.05 + 4 x 0.8) / 13.
    const double r = spot_reflectance(tape_along_x(), {0.0, 0.0094}, 0.003);
    EXPECT_NEAR(r, (9 * 0.05 + 4 * 0.8) / 13.0, 1e-12);  // 0.2808
    EXPECT_DOUBLE_EQ(spot_reflectance(tape_along_x(), {0.0, 0.0094}, 0.0), kBlackTapeReflectance);  // a point
}

TEST(SpotReflectance, IsTheThirteenPointsAverageEverywhereNearASegmentAndAnArc) {
    // spot_reflectance skips the 13 reads where clear_of_lines says no
    // line is within the spot: on a 0.25 mm grid around a segment's end and
    // a quarter arc (centre (0.5, 0.2), radius 0.2), it must equal the
    // average of the 13 reads, bit for bit (it fails with the spot's
    // radius left out of the clearance: the rim reads the tape there).
    World w = tape_along_x();
    w.lines[0].pieces = {LinePiece::segment({0.0, 0.0}, {0.5, 0.0}), LinePiece::arc({0.5, 0.2}, 0.2, -kPi / 2.0, kPi / 2.0)};
    const double d = 0.003;
    const double r = d / 2.0;
    int mixed = 0;
    for (double x = -0.02; x <= 0.75; x += 0.00025) {
        for (double y = -0.02; y <= 0.03; y += 0.00025) {
            const Eigen::Vector2d p(x, y);
            double sum = reflectance_at(w, p);
            for (int k = 0; k < 4; ++k) sum += reflectance_at(w, p + 0.5 * r * Eigen::Vector2d(std::cos(k * kPi / 2.0), std::sin(k * kPi / 2.0)));
            for (int k = 0; k < 8; ++k) sum += reflectance_at(w, p + r * Eigen::Vector2d(std::cos(k * kPi / 4.0), std::sin(k * kPi / 4.0)));
            ASSERT_EQ(spot_reflectance(w, p, d), sum / 13.0) << "at (" << x << ", " << y << ")";
            mixed += clear_of_lines(w, p, r) ? 0 : 1;
        }
    }
    EXPECT_GT(mixed, 10000);  // the grid crosses the tape, not only the floor
}

TEST(AnalogReflectance, IsLinearBetweenTheWhiteAndBlackLevelsAndClampedToTheSupply) {
    const AnalogReflectanceParams p;  // 0.3 V white, 4.5 V black, 5 V
    EXPECT_NEAR(analog_output_v(p, kWhiteReflectance), 0.3, 1e-12);
    EXPECT_NEAR(analog_output_v(p, kBlackTapeReflectance), 4.5, 1e-12);
    EXPECT_NEAR(analog_output_v(p, 0.425), 2.4, 1e-12);  // half-way
    // A mirror (r = 1): 0.3 - 4.2 / 0.75 x 0.2 = -0.82 V, clamped to 0.
    EXPECT_EQ(analog_output_v(p, 1.0), 0.0);
    // Black on a 3.3 V board is clamped to the supply.
    EXPECT_EQ(analog_output_v({0.3, 4.5, 3.3}, kBlackTapeReflectance), 3.3);
}

TEST(RcReflectance, DecaysInTheMeasuredTimesOverWhiteAndBlackAndInBetween) {
    const RcReflectanceParams p;  // [QTRAN] 2009 p. 3: 780 us white, 10 ms black
    EXPECT_NEAR(rc_decay_s(p, kWhiteReflectance), 780e-6, 1e-12);
    EXPECT_NEAR(rc_decay_s(p, kBlackTapeReflectance), 10e-3, 1e-12);
    // 1/t = g0 + g1 r: g1 = (1/780e-6 - 100) / 0.75 = 1576.068 /s,
    // g0 = 100 - 0.05 g1 = 21.197 /s; at r = 0.425: 1 / 691.026 = 1.44712 ms.
    EXPECT_NEAR(rc_decay_s(p, 0.425), 1.0 / (21.1965812 + 0.425 * 1576.0683761), 1e-9);
    EXPECT_NEAR(rc_decay_s(p, 0.0), 10e-3, 1e-12);  // darker than the tape: the tape's time
}

}  // namespace
}  // namespace ddmr::plant
