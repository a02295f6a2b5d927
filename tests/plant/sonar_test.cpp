// The HC-SR04's echo, each number worked out by hand from plant/sonar.hpp
// and ../shared/SENSORS.md section 1.
#include "plant/sonar.hpp"

#include <gtest/gtest.h>

namespace ddmr::plant {
namespace {

constexpr double kDeg = kPi / 180.0;

World wall_at_x(double x_m, double height_m = 0.2) {
    World w;
    w.walls.push_back(Wall{{x_m, -1.0}, {x_m, 1.0}, height_m});
    return w;
}

TEST(Sonar, SoundTravelsAt343Point5MetresASecondAt20Degrees) {
    EXPECT_DOUBLE_EQ(speed_of_sound_m_s(20.0), 343.5);  // 331.5 + 0.6 x 20, [PING] p. 3
    EXPECT_DOUBLE_EQ(speed_of_sound_m_s(0.0), 331.5);
}

TEST(Sonar, AWallAtOneMetreAt20DegreesEchoesFor5822Microseconds) {
    const SonarParams p;
    const std::optional<double> d = sonar_distance_m(wall_at_x(1.0), p, {0.0, 0.0}, 0.0);
    ASSERT_TRUE(d.has_value());
    EXPECT_DOUBLE_EQ(*d, 1.0);
    EXPECT_NEAR(echo_width_s(p, d), 2.0 / 343.5, 1e-15);  // 5822.416 us = 93158.7 cycles at 16 MHz
    EXPECT_NEAR(echo_width_s(p, d) * 1e6, 5822.416, 0.001);
}

TEST(Sonar, NoWallInRangeMeansTheModulesTimeout) {
    const SonarParams p;
    EXPECT_FALSE(sonar_distance_m(wall_at_x(4.5), p, {0.0, 0.0}, 0.0).has_value());  // beyond 4 m
    EXPECT_FALSE(sonar_distance_m(wall_at_x(1.0), p, {0.0, 0.0}, 180.0 * kDeg).has_value());  // behind
    EXPECT_DOUBLE_EQ(echo_width_s(p, std::nullopt), 38e-3);
}

TEST(Sonar, ANearerWallReadsAsTheMinimumRangeAndALowOneIsNotSeen) {
    const SonarParams p;  // beam 5 cm up
    EXPECT_DOUBLE_EQ(*sonar_distance_m(wall_at_x(0.01), p, {0.0, 0.0}, 0.0), 0.02);
    EXPECT_FALSE(sonar_distance_m(wall_at_x(1.0, 0.03), p, {0.0, 0.0}, 0.0).has_value());  // a 3 cm kerb
}

TEST(Sonar, TheConeSeesAWallJustInsideSevenAndAHalfDegreesAndNotJustOutside) {
    // A short wall (a post) 1 m out, at bearings 7 and 8 degrees off the axis;
    // it faces the sonar (incidence ~0).
    const SonarParams p;
    const auto post_at = [](double bearing_deg) {
        World w;
        const Eigen::Vector2d c(std::cos(bearing_deg * kDeg), std::sin(bearing_deg * kDeg));
        const Eigen::Vector2d along(-c.y(), c.x());
        w.walls.push_back(Wall{c - 0.005 * along, c + 0.005 * along, 0.2});
        return w;
    };
    EXPECT_TRUE(sonar_distance_m(post_at(7.0), p, {0.0, 0.0}, 0.0).has_value());
    EXPECT_FALSE(sonar_distance_m(post_at(8.0), p, {0.0, 0.0}, 0.0).has_value());
    EXPECT_FALSE(sonar_distance_m(post_at(-8.0), p, {0.0, 0.0}, 0.0).has_value());
}

}  // namespace
}  // namespace ddmr::plant
