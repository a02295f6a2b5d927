// The bumper and the IR obstacle module on fixture firmwares, each number
// worked out by hand (hil/parts/bumper.cpp, hil/parts/ir_obstacle.cpp).
#include <gtest/gtest.h>

#include <optional>

#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/board_file.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"

namespace ddmr::test {
namespace {

/// A wall across the x axis at x = 0.3 m, the robot moved by the test.
struct WallRig {
    TempDir dir;
    FixtureCore fx;
    plant::World world;
    plant::Pose pose{};
    std::unique_ptr<hil::PartSet> parts;
    WallRig(const std::string& fixture, const std::string& entry) : fx(fixture) {
        world.walls.push_back(plant::Wall{{0.3, -1.0}, {0.3, 1.0}, 0.2});
        parts = std::make_unique<hil::PartSet>(fx.core, uno_with_parts(dir, entry).parts, hil::PartRegistry::global(),
                                               [this] { return pose; }, &world);
    }
    void move_to(double x_m) {
        pose.x_m = x_m;
        parts->on_plant_step(fx.core.cycle());
    }
    void run(hil::Cycles cycles) { fx.core.run_until(fx.core.cycle() + cycles); }
    [[nodiscard]] int pind7() const { return (fx.core.data(0x29) >> 7) & 1; }
};

TEST(Bumper, APressedBumperStaysLowWhileTheSketchWritesItsPort) {
    // The lever's point 90 mm ahead of the axle, reaching 5 mm: pressed once
    // the wall (x = 0.3) is within 5 mm of x + 0.09, i.e. from x = 0.205.
    WallRig rig("bumper_fixture", "  - {name: bump, type: bumper, OUT: 7}\n");
    rig.run(2000);
    EXPECT_EQ(rig.fx.u8("level"), 1);  // released: the pull-up
    EXPECT_EQ(truth_value(*rig.parts, "bump.pressed"), 0.0);
    rig.move_to(0.204);
    rig.run(2000);
    EXPECT_EQ(rig.fx.u8("level"), 1);  // 6 mm away: not yet
    rig.move_to(0.206);
    rig.run(200);
    const uint16_t highs = rig.fx.u16("highs");
    rig.run(20000);  // ~1000 PORTD writes
    EXPECT_EQ(rig.fx.u16("highs"), highs) << "a write to PORTD put the pull-up back over the closed switch";
    EXPECT_EQ(rig.fx.u8("level"), 0);
    EXPECT_EQ(truth_value(*rig.parts, "bump.presses"), 1.0);
    rig.move_to(0.1);  // released
    rig.run(200);
    EXPECT_EQ(rig.fx.u8("level"), 1);
}

TEST(Bumper, BouncesAsManyTimesAsItsSettingsSay) {
    // 4 extra changes over 2 ms after the press, then LOW.
    WallRig rig("bumper_fixture", "  - {name: bump, type: bumper, OUT: 7, bounce_ms: 2, bounces: 4}\n");
    rig.run(2000);
    rig.move_to(0.21);
    int changes = 0;
    int last = rig.pind7();
    for (int k = 0; k < 3 * 16000 / 10; ++k) {  // 3 ms in 10-cycle steps
        rig.run(10);
        if (rig.pind7() != last) ++changes;
        last = rig.pind7();
    }
    EXPECT_EQ(changes, 5);  // low, high, low, high, then low to stay
    EXPECT_EQ(last, 0);
}

TEST(IrObstacle, GoesLowInsideItsRangeAndHighJustOutside) {
    // At the front (90 mm ahead of the axle), set to 15 cm: the wall at
    // x = 0.3 is within range once x + 0.09 >= 0.15.
    WallRig rig("edge_fixture", "  - {name: ir, type: ir-obstacle, OUT: 7}\n");
    rig.move_to(0.3 - 0.09 - 0.151);  // 151 mm from the wall
    rig.run(1000);
    EXPECT_EQ(rig.pind7(), 1);
    rig.move_to(0.3 - 0.09 - 0.149);  // 149 mm
    rig.run(1000);
    EXPECT_EQ(rig.pind7(), 0);
    EXPECT_EQ(truth_value(*rig.parts, "ir.detected"), 1.0);
    // Turned 20 degrees away, the wall's nearest point in the 35 degree cone
    // is 149 / cos(2.5 deg) = 149.1 mm away: still seen; at 40 degrees it is
    // outside the cone's near edge: 149 / cos(22.5) = 161 mm, out of range.
    rig.pose.theta_rad = 20.0 * 3.14159265358979323846 / 180.0;
    rig.move_to(0.3 - 0.09 * std::cos(rig.pose.theta_rad) - 0.149);
    rig.run(1000);
    EXPECT_EQ(rig.pind7(), 0);
    rig.pose.theta_rad = 40.0 * 3.14159265358979323846 / 180.0;
    rig.move_to(0.3 - 0.09 * std::cos(rig.pose.theta_rad) - 0.149);
    rig.run(1000);
    EXPECT_EQ(rig.pind7(), 1);
}

TEST(BumperAndIrObstacle, AHeldReadingWinsOverTheWorldUntilReleased) {
    // Far from the wall (x = 0): the world says released / nothing seen.
    WallRig bump("bumper_fixture", "  - {name: bump, type: bumper, OUT: 7}\n");
    bump.run(2000);
    bump.parts->set_reading("bump", "pressed", 1.0);
    bump.move_to(0.0);
    bump.run(200);
    EXPECT_EQ(bump.fx.u8("level"), 0);
    EXPECT_EQ(truth_value(*bump.parts, "bump.presses"), 1.0);
    bump.parts->set_reading("bump", "pressed", std::nullopt);
    bump.move_to(0.0);
    bump.run(200);
    EXPECT_EQ(bump.fx.u8("level"), 1);

    WallRig ir("edge_fixture", "  - {name: ir, type: ir-obstacle, OUT: 7}\n");
    ir.parts->set_reading("ir", "detected", 1.0);
    ir.move_to(0.0);
    ir.run(1000);
    EXPECT_EQ(ir.pind7(), 0);  // active low: seen
    ir.parts->set_reading("ir", "detected", std::nullopt);
    ir.move_to(0.0);
    ir.run(1000);
    EXPECT_EQ(ir.pind7(), 1);
}

}  // namespace
}  // namespace ddmr::test
