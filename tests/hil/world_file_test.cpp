// The world file: what it draws (checked by hand) and what it refuses
// (FILE:LINE, the key, the reason).
#include "hil/world_file.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "plant/units.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

plant::World world_of(const TempDir& dir, const std::string& text) {
    std::ofstream(dir / "w.yaml") << text;
    return hil::load_world_file(dir / "w.yaml");
}

/// The one-line refusal of `text`, or "" when it loads.
std::string refusal(const TempDir& dir, const std::string& text) {
    try {
        world_of(dir, text);
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

TEST(WorldFile, AnOvalPathClosesOnItselfAndIsBlackUnderTheTape) {
    TempDir dir;
    // 1 m straights joined by half circles of 0.3 m: centres (1, 0.3), (0, 0.3).
    const plant::World w = world_of(dir,
                                    "lines:\n"
                                    "  - width_m: 0.019\n"
                                    "    from_m: [0, 0]\n"
                                    "    heading_deg: 0\n"
                                    "    path:\n"
                                    "      - straight_m: 1.0\n"
                                    "      - arc: {radius_m: 0.3, turn_deg: 180}\n"
                                    "      - straight_m: 1.0\n"
                                    "      - arc: {radius_m: 0.3, turn_deg: 180}\n");
    ASSERT_EQ(w.lines.size(), 1U);
    const auto& pieces = w.lines[0].pieces;
    ASSERT_EQ(pieces.size(), 4U);
    EXPECT_NEAR(pieces[1].center_m.x(), 1.0, 1e-12);
    EXPECT_NEAR(pieces[1].center_m.y(), 0.3, 1e-12);
    EXPECT_NEAR(pieces[2].end_point().x(), 0.0, 1e-12);  // the top straight runs back to x = 0
    EXPECT_NEAR(pieces[2].end_point().y(), 0.6, 1e-12);
    EXPECT_NEAR((pieces[3].end_point() - Eigen::Vector2d(0, 0)).norm(), 0.0, 1e-12);
    EXPECT_EQ(plant::reflectance_at(w, {0.5, 0.0}), plant::kBlackTapeReflectance);
    EXPECT_EQ(plant::reflectance_at(w, {1.3, 0.3}), plant::kBlackTapeReflectance);  // the right arc's far point
    EXPECT_EQ(plant::reflectance_at(w, {-0.3, 0.3}), plant::kBlackTapeReflectance);
    EXPECT_EQ(plant::reflectance_at(w, {0.5, 0.3}), plant::kWhiteReflectance);      // inside the oval
    EXPECT_FALSE(w.start);
}

TEST(WorldFile, RightTurnsCurveClockwise) {
    TempDir dir;
    const plant::World w = world_of(dir,
                                    "lines:\n"
                                    "  - {from_m: [0, 0], heading_deg: 90, path: [{arc: {radius_m: 0.5, turn_deg: -90}}]}\n");
    // Heading +y, turning right around (0.5, 0): ends at (0.5, 0.5) heading +x.
    const plant::LinePiece& a = w.lines[0].pieces.at(0);
    EXPECT_NEAR(a.center_m.x(), 0.5, 1e-12);
    EXPECT_NEAR(a.end_point().x(), 0.5, 1e-12);
    EXPECT_NEAR(a.end_point().y(), 0.5, 1e-12);
    EXPECT_NEAR(a.end_heading_rad(), 0.0, 1e-12);
}

TEST(WorldFile, PolylinesPolygonWallsTheFloorAndTheStart) {
    TempDir dir;
    const plant::World w = world_of(dir,
                                    "floor: {reflectance: 0.7}\n"
                                    "start: {x_m: 0.1, y_m: -0.2, heading_deg: 90}\n"
                                    "lines:\n"
                                    "  - {points_m: [[0, 0], [1, 0], [1, 1]], closed: true, width_m: 0.025, reflectance: 0.1}\n"
                                    "walls:\n"
                                    "  - {from_m: [2, -1], to_m: [2, 1]}\n"
                                    "  - {polygon_m: [[-3, -3], [3, -3], [3, 3], [-3, 3]], height_m: 0.3}\n");
    EXPECT_EQ(w.floor_reflectance, 0.7);
    ASSERT_TRUE(w.start);
    EXPECT_EQ(w.start->x_m, 0.1);
    EXPECT_EQ(w.start->y_m, -0.2);
    EXPECT_DOUBLE_EQ(w.start->theta_rad, plant::kPi / 2);
    ASSERT_EQ(w.lines[0].pieces.size(), 3U);  // closed: (1, 1) back to (0, 0)
    EXPECT_EQ(plant::reflectance_at(w, {0.5, 0.5}), 0.1);  // on the closing diagonal
    EXPECT_EQ(w.lines[0].width_m, 0.025);
    ASSERT_EQ(w.walls.size(), 5U);  // one, and the arena's four sides
    EXPECT_EQ(w.walls[0].height_m, plant::Wall{}.height_m);
    EXPECT_EQ(w.walls[4].height_m, 0.3);
    EXPECT_EQ(w.walls[4].b_m, Eigen::Vector2d(-3, -3));  // the polygon closes
    EXPECT_DOUBLE_EQ(plant::nearest_wall_distance(w, {0, 0}), 2.0);
    EXPECT_TRUE(w.obstacles.empty());
    EXPECT_EQ(w.walls[0].obstacle, -1);
}

TEST(WorldFile, NamedWallsAreObstaclesAScenarioMayMove) {
    // A 0.2 m box named "box" ahead of the robot; a named wall; an unnamed arena.
    TempDir dir;
    plant::World w = world_of(dir,
                              "walls:\n"
                              "  - {polygon_m: [[0.5, -0.1], [0.7, -0.1], [0.7, 0.1], [0.5, 0.1]], name: box}\n"
                              "  - {from_m: [-1, 1], to_m: [1, 1], name: door}\n"
                              "  - {polygon_m: [[-2, -2], [2, -2], [2, 2], [-2, 2]]}\n");
    EXPECT_EQ(w.obstacles, (std::vector<std::string>{"box", "door"}));
    ASSERT_EQ(w.walls.size(), 9U);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_EQ(w.walls[i].obstacle, 0) << i;
    EXPECT_EQ(w.walls[4].obstacle, 1);
    EXPECT_EQ(w.walls[5].obstacle, -1);
    EXPECT_DOUBLE_EQ(plant::nearest_wall_distance(w, {0, 0}), 0.5);
    // Moved 0.3 m to the left, the box's nearest corner is (0.5, 0.2):
    // 0.539 m away, nearer than the door (1 m).
    plant::move_obstacle(w, *plant::find_obstacle(w, "box"), Eigen::Vector2d(0.0, 0.3));
    EXPECT_DOUBLE_EQ(w.walls[0].a_m.y(), 0.2);
    EXPECT_NEAR(plant::nearest_wall_distance(w, {0, 0}), std::hypot(0.5, 0.2), 1e-12);
    EXPECT_EQ(w.walls[4].a_m, Eigen::Vector2d(-1, 1));  // the door stays
    EXPECT_FALSE(plant::find_obstacle(w, "window"));
}

TEST(WorldFile, BadFilesAreRefusedWithTheLineAndTheKey) {
    TempDir dir;
    const std::string f = (dir / "w.yaml").string();
    // (file text, the refusal after "FILE:")
    const std::vector<std::pair<std::string, std::string>> cases{
        {"lines:\n  - {points_m: [[0, 0], [1, 0]], width_m: 0}\n",
         "2: key 'lines[0].width_m': a line needs a width above 0"},
        {"walls:\n  - from_m: [1, 1]\n    to_m: [1, 1]\n",
         "2: key 'walls[0]': a wall of zero length (two corners at the same point)"},
        {"walls:\n  - {polygon_m: [[0, 0], [1, 0]]}\n",
         "2: key 'walls[0].polygon_m': expected a list of at least 3 points [x, y]"},
        {"floor: {colour: white}\n", "1: key 'floor.colour': unknown key (expected reflectance)"},
        {"lines:\n  - {from_m: [0, 0], path: [{arc: {radius_m: 0.3, turn_deg: 0}}]}\n",
         "2: key 'lines[0].path[0].arc.turn_deg': a turn of 0 degrees draws nothing"},
        {"lines:\n  - {width_m: 0.02}\n",
         "2: key 'lines[0]': a line needs points_m (corners) or path (from_m, heading_deg and steps)"},
        {"walls:\n  - {from_m: [0, 0], to_m: [1, x]}\n", "2: key 'walls[0].to_m': 'x' is not a number"},
        {"walls:\n  - {from_m: [0, 0], to_m: [1, 0], name: box}\n  - {from_m: [0, 1], to_m: [1, 1], name: box}\n",
         "3: key 'walls[1].name': a second obstacle called 'box'"},
    };
    for (const auto& [text, why] : cases) EXPECT_EQ(refusal(dir, text), f + ":" + why) << text;
    EXPECT_EQ(refusal(dir, "floor: [1\n").rfind(f + ":", 0), 0U);  // malformed YAML names the file
    EXPECT_EQ(refusal(dir, ""), f + ": key 'world': a world file is a mapping (floor, start, lines, walls)");
}

// docs/schema/world.schema.json, run as an editor runs it, agrees with the
// reader on a full file and on the refusals above.
TEST(WorldFile, TheSchemaAcceptsAndRefusesWhatTheReaderDoes) {
    TempDir dir;
    const auto schema_accepts = [&](const std::string& text) {
        std::ofstream(dir / "s.yaml") << text;
        return run_command("/usr/bin/python3 " + sh_quote((source_dir() / "tests/tools/validate_yaml_schema.py").string()) +
                           " " + sh_quote((source_dir() / "docs/schema/world.schema.json").string()) + " " +
                           sh_quote((dir / "s.yaml").string()))
                   .exit_code == 0;
    };
    const std::string good =
        "floor: {reflectance: 0.7}\n"
        "start: {x_m: 0.1, y_m: -0.2, heading_deg: 90}\n"
        "lines:\n"
        "  - {points_m: [[0, 0], [1, 0], [1, 1]], closed: true, width_m: 0.025, reflectance: 0.1}\n"
        "  - {from_m: [0, 0], heading_deg: 0, path: [{straight_m: 1.0}, {arc: {radius_m: 0.3, turn_deg: 180}}]}\n"
        "walls:\n"
        "  - {from_m: [2, -1], to_m: [2, 1]}\n"
        "  - {polygon_m: [[-3, -3], [3, -3], [3, 3]], height_m: 0.3}\n";
    EXPECT_EQ(refusal(dir, good), "");
    EXPECT_TRUE(schema_accepts(good));
    for (const char* bad : {"lines:\n  - {points_m: [[0, 0], [1, 0]], width_m: 0}\n",
                            "walls:\n  - {polygon_m: [[0, 0], [1, 0]]}\n", "floor: {colour: white}\n",
                            "lines:\n  - {from_m: [0, 0], path: [{arc: {radius_m: 0.3, turn_deg: 0}}]}\n",
                            "lines:\n  - {width_m: 0.02}\n", "walls:\n  - {from_m: [0, 0]}\n",
                            "lines:\n  - {points_m: [[0, 0], [1, 0]], from_m: [0, 0], path: [{straight_m: 1}]}\n"}) {
        EXPECT_NE(refusal(dir, bad), "") << bad;
        EXPECT_FALSE(schema_accepts(bad)) << bad;
    }
}

}  // namespace
}  // namespace ddmr::test
