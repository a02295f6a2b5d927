// The world's geometry, each number worked out by hand.
#include "plant/world.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

constexpr double kDeg = kPi / 180.0;

FloorLine tape(std::vector<LinePiece> pieces, double reflectance = kBlackTapeReflectance) {
    FloorLine l;
    l.pieces = std::move(pieces);
    l.reflectance = reflectance;
    return l;
}

Wall wall(double ax, double ay, double bx, double by, double height_m = 0.2) {
    return Wall{{ax, ay}, {bx, by}, height_m};
}

/// An HC-SR04 at the origin facing +x: 15 degrees full angle, 4 m.
Cone sonar(double max_incidence_deg = 45.0) {
    Cone c;
    c.half_angle_rad = 7.5 * kDeg;
    c.max_incidence_rad = max_incidence_deg * kDeg;
    c.max_range_m = 4.0;
    c.height_m = 0.1;
    return c;
}

TEST(World, ASegmentsClosestPointIsTheFootOfThePerpendicularOrAnEnd) {
    const LinePiece s = LinePiece::segment({0, 0}, {1, 0});
    EXPECT_TRUE(closest_point(s, {0.3, 0.2}).isApprox(Eigen::Vector2d(0.3, 0)));
    EXPECT_TRUE(closest_point(s, {1.5, -0.2}).isApprox(Eigen::Vector2d(1, 0)));
    EXPECT_DOUBLE_EQ(s.length_m(), 1.0);
}

TEST(World, AnArcsClosestPointIsOnItsRadiusInsideTheSweepElseAnEnd) {
    // A quarter circle of 0.5 m from (0.5, 0) to (0, 0.5).
    const LinePiece a = LinePiece::arc({0, 0}, 0.5, 0.0, kPi / 2);
    const double r = 0.5 / std::sqrt(2.0);
    EXPECT_TRUE(closest_point(a, {0.3, 0.3}).isApprox(Eigen::Vector2d(r, r)));
    EXPECT_TRUE(closest_point(a, {-0.5, 0.1}).isApprox(Eigen::Vector2d(0, 0.5)));  // 0.640 m vs 1.005 m
    EXPECT_TRUE(closest_point(a, {0.2, -0.5}).isApprox(Eigen::Vector2d(0.5, 0)));
    // The same quarter drawn clockwise from (0, 0.5).
    const LinePiece cw = LinePiece::arc({0, 0}, 0.5, kPi / 2, -kPi / 2);
    EXPECT_TRUE(closest_point(cw, {0.3, 0.3}).isApprox(Eigen::Vector2d(r, r)));
    EXPECT_TRUE(closest_point(cw, {-0.3, -0.1}).isApprox(Eigen::Vector2d(0, 0.5)));  // 0.671 m vs 0.806 m
    EXPECT_DOUBLE_EQ(a.length_m(), 0.5 * kPi / 2);
}

TEST(World, AnOvalsHalfCircleEndsWhereTheNextStraightStarts) {
    // Around (1, 0.3), radius 0.3, from straight below the centre, half a turn
    // counter-clockwise: (1, 0) to (1, 0.6), heading back along -x.
    const LinePiece a = LinePiece::arc({1, 0.3}, 0.3, -kPi / 2, kPi);
    EXPECT_TRUE(a.start_point().isApprox(Eigen::Vector2d(1, 0)));
    EXPECT_NEAR(a.end_point().x(), 1.0, 1e-12);
    EXPECT_NEAR(a.end_point().y(), 0.6, 1e-12);
    EXPECT_NEAR(a.end_heading_rad(), kPi, 1e-12);
    EXPECT_NEAR(LinePiece::segment({0, 0}, {0, -2}).end_heading_rad(), -kPi / 2, 1e-12);
}

TEST(World, ThePointIsOnTheLineWithinHalfItsWidth) {
    World w;
    w.lines.push_back(tape({LinePiece::segment({0, 0}, {1, 0})}));  // 19 mm wide
    EXPECT_EQ(reflectance_at(w, {0.5, 0.009}), kBlackTapeReflectance);   // 9 mm < 9.5 mm
    EXPECT_EQ(reflectance_at(w, {0.5, -0.0095}), kBlackTapeReflectance);
    EXPECT_EQ(reflectance_at(w, {0.5, 0.010}), kWhiteReflectance);       // 10 mm: the floor
    EXPECT_EQ(reflectance_at(w, {1.009, 0.0}), kBlackTapeReflectance);    // the ends are round: 9 mm past it
    EXPECT_EQ(reflectance_at(w, {1.007, 0.007}), kWhiteReflectance);      // 9.9 mm from the end point
    EXPECT_EQ(reflectance_at(World{}, {0, 0}), kWhiteReflectance);
}

TEST(World, AnArcCoversWhatIsWithinHalfItsWidthOfItsSweepAndNothingElse) {
    // A quarter circle of 0.3 m around (1, 0.3) from (1.3, 0.3) to (1, 0.6),
    // 19 mm wide. reflectance_at first rejects points farther than 9.5 mm
    // from the whole circle; on a grid that crosses the circle inside and
    // outside the sweep, round its round ends and the centre, its answer
    // must be the distance to the arc's nearest point.
    World w;
    const LinePiece arc = LinePiece::arc({1, 0.3}, 0.3, 0.0, kPi / 2);
    w.lines.push_back(tape({arc}));
    int on = 0;
    int near_circle_off_sweep = 0;
    for (int i = -400; i <= 400; ++i) {
        for (int j = -400; j <= 400; ++j) {
            const Eigen::Vector2d p(1.0 + i * 0.001, 0.3 + j * 0.001);
            const bool covered = (p - closest_point(arc, p)).norm() <= 0.0095;
            EXPECT_EQ(reflectance_at(w, p), covered ? kBlackTapeReflectance : kWhiteReflectance) << p.transpose();
            on += covered ? 1 : 0;
            const double off_circle = std::fabs((p - Eigen::Vector2d(1, 0.3)).norm() - 0.3);
            near_circle_off_sweep += off_circle <= 0.0095 && !covered ? 1 : 0;
        }
    }
    // A 19 mm band along a quarter of a 0.3 m circle (0.471 m): ~0.0090 m^2,
    // ~9000 points of 1 mm^2, plus the two round ends; and the three other
    // quarters of the circle's band lie near the circle but off the sweep.
    EXPECT_GT(on, 8500);
    EXPECT_LT(on, 9600);
    EXPECT_GT(near_circle_off_sweep, 20000);
}

TEST(World, WhereLinesCrossTheOneListedLastIsOnTop) {
    World w;
    w.lines.push_back(tape({LinePiece::segment({0, -1}, {0, 1})}, 0.05));
    w.lines.push_back(tape({LinePiece::segment({-1, 0}, {1, 0})}, 0.3));
    EXPECT_EQ(reflectance_at(w, {0, 0}), 0.3);
    EXPECT_EQ(reflectance_at(w, {0, 0.5}), 0.05);
}

TEST(World, TheLinesOffsetIsPositiveToTheLeftOfTheHeading) {
    World w;
    w.lines.push_back(tape({LinePiece::segment({0, 0}, {1, 0})}));
    const auto ahead = line_offset(w, {0.5, -0.01}, 0.0);  // driving +x, the line 1 cm to the left
    ASSERT_TRUE(ahead);
    EXPECT_NEAR(ahead->lateral_m, 0.01, 1e-12);
    EXPECT_NEAR(ahead->distance_m, 0.01, 1e-12);
    EXPECT_NEAR(line_offset(w, {0.5, -0.01}, kPi)->lateral_m, -0.01, 1e-12);  // driving -x: to the right
    EXPECT_FALSE(line_offset(World{}, {0, 0}, 0.0));
}

TEST(World, TheConePicksTheNearestWallInsideItAndIgnoresOneJustOutside) {
    World w;
    w.walls.push_back(wall(1.0, -1.0, 1.0, 1.0));  // square across the beam at 1.000 m
    // A nearer wall at x = 0.5 whose lower end lies at 7.6 degrees: outside
    // the 7.5-degree half angle.
    w.walls.push_back(wall(0.5, 0.5 * std::tan(7.6 * kDeg), 0.5, 1.0));
    auto hit = cast_cone(w, sonar());
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->wall, 0U);
    EXPECT_DOUBLE_EQ(hit->distance_m, 1.0);
    EXPECT_DOUBLE_EQ(hit->incidence_rad, 0.0);
    // Its lower end at 7.4 degrees: inside; the nearest point of it in the
    // cone is that end, 0.5 / cos(7.4 deg) = 0.504200 m away, struck at 7.4 deg.
    w.walls[1].a_m.y() = 0.5 * std::tan(7.4 * kDeg);
    hit = cast_cone(w, sonar());
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->wall, 1U);
    EXPECT_NEAR(hit->distance_m, 0.5 / std::cos(7.4 * kDeg), 1e-12);
    EXPECT_NEAR(hit->incidence_rad, 7.4 * kDeg, 1e-12);
}

TEST(World, AWallStruckTooObliquelyGivesNoEchoAndAFartherOneMay) {
    // A wall through (1, 0) whose normal points 60 degrees off the beam: its
    // foot of perpendicular (0.5 m away, at 60 degrees) lies outside the cone;
    // inside it, the nearest point is on the 7.5-degree edge, at
    // 0.5 / cos(60 - 7.5 deg) = 0.821348 m, struck at 52.5 degrees.
    const Eigen::Vector2d along(-std::sin(60 * kDeg), std::cos(60 * kDeg));
    const Eigen::Vector2d p0 = Eigen::Vector2d(1, 0) - 2.0 * along;
    const Eigen::Vector2d p1 = Eigen::Vector2d(1, 0) + 2.0 * along;
    World w;
    w.walls.push_back(wall(p0.x(), p0.y(), p1.x(), p1.y()));
    auto hit = cast_cone(w, sonar(55.0));
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->distance_m, 0.5 / std::cos(52.5 * kDeg), 1e-12);
    EXPECT_NEAR(hit->incidence_rad, 52.5 * kDeg, 1e-12);
    EXPECT_FALSE(cast_cone(w, sonar(45.0)));
    w.walls.push_back(wall(3.0, -1.0, 3.0, 1.0));
    hit = cast_cone(w, sonar(45.0));
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->wall, 1U);
    EXPECT_DOUBLE_EQ(hit->distance_m, 3.0);
}

TEST(World, TheConeSeesNothingBeyondItsRangeOrBelowItsHeightOrBehindIt) {
    World w;
    w.walls.push_back(wall(4.5, -1, 4.5, 1));           // beyond 4 m
    w.walls.push_back(wall(0.5, -1, 0.5, 1, 0.05));      // a 5 cm kerb under a beam at 10 cm
    w.walls.push_back(wall(-0.3, -1, -0.3, 1));         // behind
    EXPECT_FALSE(cast_cone(w, sonar()));
    w.walls[1].height_m = 0.1;
    ASSERT_TRUE(cast_cone(w, sonar()));
    EXPECT_DOUBLE_EQ(cast_cone(w, sonar())->distance_m, 0.5);
}

TEST(World, TheNearestWallIsAtTheFootOfThePerpendicular) {
    World w;
    EXPECT_EQ(nearest_wall_distance(w, {0, 0}), std::numeric_limits<double>::infinity());
    w.walls.push_back(wall(1.0, -1.0, 1.0, 1.0));
    w.walls.push_back(wall(-2.0, 3.0, 2.0, 3.0));
    EXPECT_DOUBLE_EQ(nearest_wall_distance(w, {0, 0}), 1.0);
    EXPECT_DOUBLE_EQ(nearest_wall_distance(w, {0, 2.5}), 0.5);
    EXPECT_DOUBLE_EQ(nearest_wall_distance(w, {2, 2}), 1.0);  // (2, 3) is 1 m away, (1, 1) 1.414 m
}

}  // namespace
}  // namespace ddmr::plant
