// The HC-SR04 part on a fixture firmware: ECHO's edges at their exact cycles
// for a wall worked out by hand (hil/parts/ultrasonic_hcsr04.cpp,
// plant/sonar.hpp).
#include <gtest/gtest.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "hil/cycle_time.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/board_file.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"

namespace ddmr::test {
namespace {

struct Edges {
    hil::Cycles trig_fall = 0, echo_rise = 0, echo_fall = 0;
};

struct SonarRig {
    TempDir dir;
    FixtureCore fx{"sonar_fixture"};
    plant::World world;
    plant::Pose pose{};
    std::unique_ptr<hil::PartSet> parts;

    /// A wall across the x axis at `wall_x_m`; the sensor `entry`.
    SonarRig(double wall_x_m, const std::string& entry) {
        world.walls.push_back(plant::Wall{{wall_x_m, -1.0}, {wall_x_m, 1.0}, 0.2});
        parts = std::make_unique<hil::PartSet>(fx.core, uno_with_parts(dir, entry).parts, hil::PartRegistry::global(),
                                               [this] { return pose; }, &world);
    }
    [[nodiscard]] bool trig() const { return ((fx.core.data(0x2B) >> 7) & 1) != 0; }  // PORTD bit 7
    [[nodiscard]] bool echo() const { return (fx.core.data(0x23) & 1) != 0; }         // PINB bit 0
    /// Pings once and watches every cycle until ECHO falls (or `limit` cycles).
    Edges ping(uint8_t n, hil::Cycles limit) {
        Edges e;
        fx.poke("request", n);
        const hil::Cycles end = fx.core.cycle() + limit;
        bool was_trig = false;
        while (fx.core.cycle() < end) {
            fx.core.run_until(fx.core.cycle() + 1);
            if (was_trig && !trig()) e.trig_fall = fx.core.cycle();
            was_trig = trig();
            if (e.echo_rise == 0 && echo()) e.echo_rise = fx.core.cycle();
            if (e.echo_rise != 0 && !echo()) {
                e.echo_fall = fx.core.cycle();
                break;
            }
        }
        return e;
    }
};

const std::string kSonar = "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 0}\n";

TEST(UltrasonicHcsr04, AWallAtOneMetreAt20DegreesHoldsEchoFor93159Cycles) {
    SonarRig rig(1.0, kSonar);
    rig.fx.core.run_until(FixtureCore::kPastStartup);
    const Edges e = rig.ping(1, 200000);
    ASSERT_NE(e.echo_fall, 0U) << "no echo";
    // 2 x 1.000 m / 343.5 m/s = 5822.416 us = 93158.66 cycles: 93159. Each
    // edge is raised at the first instruction boundary at or after its
    // cycle, and the fixture's loop has 2-cycle instructions: either edge
    // may be seen a cycle late.
    EXPECT_NEAR(static_cast<double>(e.echo_fall - e.echo_rise), 93159.0, 1.0);
    // The 200 us burst after TRIG's falling edge (seen at the end of the
    // instruction that cleared it: 2 cycles).
    EXPECT_NEAR(static_cast<double>(e.echo_rise - e.trig_fall), 3200.0, 2.0);
    EXPECT_DOUBLE_EQ(truth_value(*rig.parts, "sonar.distance_m"), 1.0);
    EXPECT_NEAR(truth_value(*rig.parts, "sonar.echo_us"), 5822.416, 0.001);
    EXPECT_EQ(truth_value(*rig.parts, "sonar.pings"), 1.0);
}

TEST(UltrasonicHcsr04, TheWarmerTheAirTheShorterTheEcho) {
    SonarRig rig(1.0, "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 0, temperature_c: 35}\n");
    rig.fx.core.run_until(FixtureCore::kPastStartup);
    const Edges e = rig.ping(1, 200000);
    // c = 331.5 + 21 = 352.5 m/s: 2 / 352.5 s = 90780.85 cycles (+-1 as above).
    EXPECT_NEAR(static_cast<double>(e.echo_fall - e.echo_rise), 90781.0, 1.0);
    EXPECT_NEAR(truth_value(*rig.parts, "sonar.echo_us"), 2e6 / 352.5, 1e-9);
}

TEST(UltrasonicHcsr04, NoWallInRangeHoldsEchoForTheModulesTimeout) {
    SonarRig rig(4.5, kSonar);
    rig.fx.core.run_until(FixtureCore::kPastStartup);
    const Edges e = rig.ping(1, 700000);
    EXPECT_NEAR(static_cast<double>(e.echo_fall - e.echo_rise), 38000.0 * 16.0, 1.0);  // 38 ms
    EXPECT_EQ(truth_value(*rig.parts, "sonar.distance_m"), 0.0);
}

TEST(UltrasonicHcsr04, ASensorTurnedAwaySeesNoWallAndTheMountOffsetCounts) {
    // 90 degrees to the left: the wall at x = 1 m lies along its axis, not across it.
    SonarRig left(1.0, "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 0, heading_deg: 90}\n");
    left.fx.core.run_until(FixtureCore::kPastStartup);
    (void)left.ping(1, 700000);
    EXPECT_EQ(truth_value(*left.parts, "sonar.distance_m"), 0.0);
    // 70 mm ahead of the axle: 0.93 m to the wall.
    SonarRig ahead(1.0, "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 70}\n");
    ahead.fx.core.run_until(FixtureCore::kPastStartup);
    (void)ahead.ping(1, 200000);
    EXPECT_DOUBLE_EQ(truth_value(*ahead.parts, "sonar.distance_m"), 0.93);
}

TEST(UltrasonicHcsr04, AHeldDistanceReplacesTheWorldUntilReleased) {
    SonarRig rig(1.0, kSonar);
    rig.fx.core.run_until(FixtureCore::kPastStartup);
    rig.parts->set_reading("sonar", "distance_m", 0.5);
    // 2 x 0.5 m / 343.5 m/s = 2911.208 us = 46579.33 cycles (+-1 as above).
    Edges e = rig.ping(1, 200000);
    EXPECT_NEAR(static_cast<double>(e.echo_fall - e.echo_rise), 46579.0, 1.0);
    // Past max_range_m (4 m): no echo, the module's 38 ms timeout.
    rig.parts->set_reading("sonar", "distance_m", 4.5);
    rig.fx.core.run_until(rig.fx.core.cycle() + 100000);
    e = rig.ping(2, 700000);
    EXPECT_NEAR(static_cast<double>(e.echo_fall - e.echo_rise), 38000.0 * 16.0, 1.0);
    // Nearer than min_range_m (2 cm): read as 2 cm, as the cone would give it.
    rig.parts->set_reading("sonar", "distance_m", 0.005);
    rig.fx.core.run_until(rig.fx.core.cycle() + 100000);
    (void)rig.ping(3, 200000);
    EXPECT_DOUBLE_EQ(truth_value(*rig.parts, "sonar.distance_m"), 0.02);
    rig.parts->set_reading("sonar", "distance_m", std::nullopt);
    rig.fx.core.run_until(rig.fx.core.cycle() + 100000);
    (void)rig.ping(4, 200000);
    EXPECT_DOUBLE_EQ(truth_value(*rig.parts, "sonar.distance_m"), 1.0);
}

TEST(UltrasonicHcsr04, HeldReadingsAreCheckedByName) {
    SonarRig rig(1.0, kSonar);
    const auto message = [&](const std::string& part, const std::string& reading, double value) -> std::string {
        try {
            rig.parts->set_reading(part, reading, value);
        } catch (const std::invalid_argument& e) {
            return e.what();
        }
        return "";
    };
    EXPECT_EQ(message("front", "distance_m", 1.0),
              "sensor 'front': the board has no such part; the board's parts with settable readings are: sonar "
              "(ultrasonic)");
    EXPECT_EQ(message("sonar", "range", 1.0), "sensor 'sonar' (ultrasonic) has no reading 'range'; it has: distance_m");
    EXPECT_EQ(message("sonar", "distance_m", -0.1).rfind("sensor 'sonar': distance_m = -0.1 is outside [0, 100]", 0), 0U);
}

TEST(UltrasonicHcsr04, ATriggerWhileTheEchoIsHighIsIgnored) {
    SonarRig rig(1.0, kSonar);
    rig.fx.core.run_until(FixtureCore::kPastStartup);
    rig.fx.poke("request", 1);
    rig.fx.core.run_until(rig.fx.core.cycle() + 20000);  // ECHO high by now
    ASSERT_TRUE(rig.echo());
    ASSERT_TRUE(rig.fx.handshake("request", "done", 2, 2000));
    rig.fx.core.run_until(rig.fx.core.cycle() + 200000);
    EXPECT_EQ(truth_value(*rig.parts, "sonar.pings"), 1.0);
}

/// Our own sketches, each reading a wall 1.000 m ahead its own way: the
/// distance in cm (58 us a cm, [SR04]) after a few pings.
class SonarSketch : public ::testing::TestWithParam<const char*> {};

TEST_P(SonarSketch, ReadsAWallAtOneMetreAsOneHundredCentimetres) {
    TempDir dir;
    FixtureCore fx{GetParam()};
    plant::World world;
    world.walls.push_back(plant::Wall{{1.07, -1.0}, {1.07, 1.0}, 0.2});  // 1.000 m from the sensor at x = 70 mm
    const hil::PartSet parts(fx.core, uno_with_parts(dir, "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8}\n").parts,
                             hil::PartRegistry::global(), [] { return plant::Pose{}; }, &world);
    ASSERT_TRUE(fx.run_until_u8("pings", 3, hil::ms_to_cycles(400, fx.core.clock_hz())));
    // ECHO is high 5822 us: pulseIn() misses the Timer0 interrupts' cycles
    // (a few us), micros() steps by 4 us, the Timer2 poll by 24 us.
    EXPECT_NEAR(static_cast<double>(fx.u16("echo_us")), 5822.0, 30.0);
    EXPECT_GE(fx.u16("distance_cm"), 99);
    EXPECT_LE(fx.u16("distance_cm"), 100);
    EXPECT_EQ(truth_value(parts, "sonar.pings"), 3.0);
}

INSTANTIATE_TEST_SUITE_P(Sketches, SonarSketch, ::testing::Values("sonar_pulsein", "sonar_pcint", "sonar_timer2"));

}  // namespace
}  // namespace ddmr::test
