// world.json (tools/common/world_json.hpp): what the report draws, checked
// on a world worked out by hand.
#include "common/world_json.hpp"

#include <gtest/gtest.h>

#include "plant/units.hpp"

namespace ddmr::tools {
namespace {

TEST(WorldJson, ArcsAreSampledEveryTwoDegreesAndWallsKeepTheirObstacle) {
    plant::World w;
    plant::FloorLine line;
    line.pieces.push_back(plant::LinePiece::segment({0, 0}, {1, 0}));
    // A half circle of 0.3 m around (1, 0.3), from straight below it: 90
    // pieces of 2 degrees, ending at (1, 0.6).
    line.pieces.push_back(plant::LinePiece::arc({1, 0.3}, 0.3, -plant::kPi / 2, plant::kPi));
    w.lines.push_back(line);
    w.obstacles = {"box"};
    w.walls.push_back(plant::Wall{{2, -1}, {2, 1}, 0.3, 0});
    w.walls.push_back(plant::Wall{{-2, -1}, {-2, 1}, 0.2, -1});
    const auto j = world_json(w);
    const auto& pts = j["lines"][0]["points_m"];
    ASSERT_EQ(pts.size(), 1U + 1U + 90U);  // the start, the segment's end, the arc's 90 steps
    EXPECT_EQ(pts[1], nlohmann::ordered_json::array({1.0, 0.0}));
    EXPECT_EQ(pts.back(), nlohmann::ordered_json::array({1.0, 0.6}));
    EXPECT_EQ(pts[46], nlohmann::ordered_json::array({1.3, 0.3}));  // halfway round: 90 degrees
    EXPECT_EQ(j["lines"][0]["width_m"], 0.019);
    EXPECT_EQ(j["walls"][0]["obstacle"], "box");
    EXPECT_EQ(j["walls"][0]["height_m"], 0.3);
    EXPECT_FALSE(j["walls"][1].contains("obstacle"));
    EXPECT_FALSE(j.contains("start"));
}

}  // namespace
}  // namespace ddmr::tools
