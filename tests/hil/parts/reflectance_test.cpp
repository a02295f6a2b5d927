// The reflectance part's three outputs on fixture firmwares, each number
// worked out by hand (hil/parts/reflectance.cpp, plant/reflectance_sensor.hpp).
#include <gtest/gtest.h>

#include <optional>

#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/board_file.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"

namespace ddmr::test {
namespace {

/// A 19 mm black tape along y at x = 0.1 m.
plant::World tape_at_x_100mm() {
    plant::World w;
    w.lines.push_back(plant::FloorLine{{plant::LinePiece::segment({0.1, -1.0}, {0.1, 1.0})}});
    return w;
}

/// A robot pose a test moves, and the parts reading it.
struct Rig {
    TempDir dir;
    FixtureCore fx;
    plant::World world = tape_at_x_100mm();
    plant::Pose pose{};
    hil::PartSet parts;
    Rig(const std::string& fixture, const std::string& entries)
        : fx(fixture), parts(fx.core, uno_with_parts(dir, entries).parts, hil::PartRegistry::global(),
                             [this] { return pose; }, &world) {}
    /// Puts the robot at x and lets the parts see it (one plant step).
    void move_to(double x_m) {
        pose.x_m = x_m;
        parts.on_plant_step(fx.core.cycle());
    }
    [[nodiscard]] int pind7() const { return (fx.core.data(0x29) >> 7) & 1; }  // PIND bit 7
};

TEST(Reflectance, ADigitalModuleGoesHighOverTheTapeAndLowOverWhite) {
    // The spot 40 mm ahead of the axle: on the tape when the robot is at x = 60 mm.
    Rig rig("edge_fixture", "  - {name: ir, type: reflectance, OUT: 7, x_mm: 40}\n");
    rig.fx.core.run_until(1000);
    EXPECT_EQ(rig.pind7(), 0);  // at x = 0 the spot is on white (40 mm from the tape)
    rig.move_to(0.06);
    rig.fx.core.run_until(2000);
    EXPECT_EQ(rig.pind7(), 1);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "ir.reflectance"), plant::kBlackTapeReflectance);
    EXPECT_EQ(truth_value(rig.parts, "ir.level"), 1.0);
    rig.move_to(0.06 + 0.0095 + 0.0016);  // the spot's rim just past the tape's edge
    rig.fx.core.run_until(3000);
    EXPECT_EQ(rig.pind7(), 0);
}

TEST(Reflectance, ALowOnDarkModuleIsTheOppositeAndTheThresholdSetsTheEdge) {
    Rig rig("edge_fixture", "  - {name: ir, type: reflectance, OUT: 7, x_mm: 40, active: low-on-dark}\n");
    rig.fx.core.run_until(1000);
    EXPECT_EQ(rig.pind7(), 1);
    // The spot's centre 0.1 mm inside the tape's edge: 9 of 13 points dark,
    // 0.2808 (tests/plant/reflectance_sensor_test.cpp): darker than 0.425.
    rig.move_to(0.06 + 0.0094);
    rig.fx.core.run_until(2000);
    EXPECT_EQ(rig.pind7(), 0);
    EXPECT_NEAR(truth_value(rig.parts, "ir.reflectance"), (9 * 0.05 + 4 * 0.8) / 13.0, 1e-12);
}

TEST(Reflectance, AnAnalogSensorGivesTheAdcCodesOfItsWhiteAndBlackVoltages) {
    Rig rig("adc_fixture", "  - {name: qtr, type: reflectance, output: analog, OUT: A2, x_mm: 40}\n");
    ASSERT_TRUE(rig.fx.run_until_u8("rounds", 2, 20 * 16000));
    EXPECT_EQ(rig.fx.u16("codes", 2), 61);  // white: floor(0.3 V x 1024 / 5 V) = 61
    rig.move_to(0.06);
    const uint8_t now = rig.fx.u8("rounds");
    ASSERT_TRUE(rig.fx.run_until_u8("rounds", static_cast<uint8_t>(now + 2), 20 * 16000));
    EXPECT_EQ(rig.fx.u16("codes", 2), 921);  // black: floor(4.5 x 1024 / 5) = 921
    EXPECT_NEAR(truth_value(rig.parts, "qtr.volts"), 4.5, 1e-12);
}

TEST(Reflectance, AHeldReflectanceIsWhatTheSensorSeesUntilReleased) {
    // On white at x = 0; held at 0.5, on the line through white (0.8, 0.3 V)
    // and black tape (0.05, 4.5 V) of plant/reflectance_sensor.hpp:
    // 0.3 + (4.5 - 0.3) / (0.05 - 0.8) x (0.5 - 0.8) = 0.3 + 1.68 = 1.98 V.
    Rig rig("adc_fixture", "  - {name: qtr, type: reflectance, output: analog, OUT: A2, x_mm: 40}\n");
    ASSERT_TRUE(rig.fx.run_until_u8("rounds", 2, 20 * 16000));
    rig.parts.set_reading("qtr", "reflectance", 0.5);
    rig.move_to(0.0);
    uint8_t now = rig.fx.u8("rounds");
    ASSERT_TRUE(rig.fx.run_until_u8("rounds", static_cast<uint8_t>(now + 2), 20 * 16000));
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "qtr.reflectance"), 0.5);
    EXPECT_NEAR(truth_value(rig.parts, "qtr.volts"), 1.98, 1e-12);
    EXPECT_EQ(rig.fx.u16("codes", 2), 405);  // floor(1.98 x 1024 / 5) = floor(405.5)
    rig.parts.set_reading("qtr", "reflectance", std::nullopt);
    rig.move_to(0.0);
    now = rig.fx.u8("rounds");
    ASSERT_TRUE(rig.fx.run_until_u8("rounds", static_cast<uint8_t>(now + 2), 20 * 16000));
    EXPECT_EQ(rig.fx.u16("codes", 2), 61);  // white again
}

TEST(Reflectance, AnRcLineDecaysIn780MicrosecondsOverWhiteAnd10MillisecondsOverBlack) {
    Rig rig("rc_fixture", "  - {name: qtr, type: reflectance, output: rc, OUT: 7, x_mm: 40}\n");
    // Timer1 at /8 counts 2 ticks a microsecond; the loop that polls PIND
    // reads TCNT1 every few cycles (a tick or two late at most).
    ASSERT_TRUE(rig.fx.handshake("request", "done", 1, 2 * 16000));
    EXPECT_NEAR(rig.fx.u16("decay_ticks"), 1560, 3);  // 780 us
    EXPECT_NEAR(truth_value(rig.parts, "qtr.decay_us"), 780.0, 1e-9);
    rig.move_to(0.06);
    ASSERT_TRUE(rig.fx.handshake("request", "done", 2, 12 * 16000));
    EXPECT_NEAR(rig.fx.u16("decay_ticks"), 20000, 3);  // 10 ms
    EXPECT_NEAR(truth_value(rig.parts, "qtr.decay_us"), 10000.0, 1e-9);
}

TEST(Reflectance, AnAnalogSensorOnAPinWithoutAnAdcIsRefusedWhereTheBoardFileSaysSo) {
    const std::string error = board_load_error(
        "board: uno\nparts:\n  - {name: qtr, type: reflectance, output: analog, OUT: 7}\n" + kUnoTestWheels);
    EXPECT_NE(error.find("b.yaml:3: key 'parts.qtr.OUT': an analog reflectance sensor needs an ADC input: pin 7 of the "),
              std::string::npos)
        << error;
}

}  // namespace
}  // namespace ddmr::test
