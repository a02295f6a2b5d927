// The world's truth columns (hil/world_truth.hpp), worked out by hand.
#include "hil/world_truth.hpp"

#include <gtest/gtest.h>

namespace ddmr::test {
namespace {

TEST(WorldTruth, APlainFloorAddsNoColumns) {
    const plant::World plain;
    const plant::Robot robot;
    const hil::WorldTruth t(plain, robot);
    EXPECT_TRUE(t.columns().empty());
    std::vector<double> v;
    t.values(v);
    EXPECT_TRUE(v.empty());
}

TEST(WorldTruth, GivesTheLinesOffsetAcrossTheHeadingAndTheNearestWall) {
    plant::World w;
    w.lines.push_back(plant::FloorLine{{plant::LinePiece::segment({-1, 0.03}, {3, 0.03})}});  // 30 mm left of x
    w.walls.push_back(plant::Wall{{2.0, -1.0}, {2.0, 1.0}, 0.2});
    plant::Robot robot;
    robot.reset(plant::Pose{0.5, 0.0, 0.0});
    const hil::WorldTruth t(w, robot);
    EXPECT_EQ(t.columns(), (std::vector<std::string>{"line_offset_m", "wall_distance_m", "contact", "contacts"}));
    std::vector<double> v;
    t.values(v);
    ASSERT_EQ(v.size(), 4U);
    EXPECT_NEAR(v[0], 0.03, 1e-12);  // the line 30 mm to the left
    EXPECT_NEAR(v[1], 1.5, 1e-12);   // the wall at x = 2 m
    EXPECT_EQ(v[2], 0.0);            // not touching it
    EXPECT_EQ(v[3], 0.0);
    robot.reset(plant::Pose{0.5, 0.0, 3.14159265358979323846});  // heading -x: the same line is to the right
    v.clear();
    t.values(v);
    EXPECT_NEAR(v[0], -0.03, 1e-12);
}

}  // namespace
}  // namespace ddmr::test
