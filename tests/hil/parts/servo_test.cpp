// The servo part on a fixture that makes its pulses as the Arduino Servo
// library does, each number worked out by hand (hil/parts/servo.cpp).
#include <gtest/gtest.h>

#include "hil/cycle_time.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/board_file.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"

namespace ddmr::test {
namespace {

struct ServoRig {
    TempDir dir;
    FixtureCore fx;
    hil::PartSet parts;
    explicit ServoRig(const std::string& entry, const plant::World* world = nullptr,
                      const std::string& fixture = "servo_fixture")
        : fx(fixture), parts(fx.core, uno_with_parts(dir, entry).parts, hil::PartRegistry::global(), [] { return plant::Pose{}; },
                world) {}
    /// Pulses of `us` microseconds (0.5 us ticks) from now.
    void send_us(double us) {
        fx.core.run_until(std::max<hil::Cycles>(fx.core.cycle(), FixtureCore::kPastStartup));
        const auto ticks = static_cast<uint16_t>(us * 2.0);
        fx.core.raw()->data[fx.address("pulse_ticks")] = static_cast<uint8_t>(ticks & 0xFF);
        fx.core.raw()->data[fx.address("pulse_ticks") + 1] = static_cast<uint8_t>(ticks >> 8);
    }
    void run_ms(double ms) { fx.core.run_until(fx.core.cycle() + hil::ms_to_cycles(ms, fx.core.clock_hz())); }
    /// Runs `ms` in plant steps of 1 ms.
    void step_ms(int ms) {
        for (int i = 0; i < ms; ++i) {
            run_ms(1.0);
            parts.on_plant_step(fx.core.cycle());
        }
    }
};

const std::string kServo = "  - {name: pan, type: servo, SIGNAL: 9}\n";

TEST(Servo, WriteNinetyIs1472MicrosecondsAndNinetyDegrees) {
    // Servo::write(90): map(90, 0, 180, 544, 2400) = 544 + 90 x 1856 / 180 = 1472 us.
    ServoRig rig(kServo);
    rig.send_us(1472);
    rig.run_ms(100);
    // The fixture's interrupt makes each pulse 22 cycles (1.375 us) longer
    // than its ticks: the branch that ends a pulse writes PORTB later in the
    // ISR than the one that starts it (the Servo library trims 2 us for the
    // same reason, TRIM_DURATION). (1472 - 544) / 1856 x 180 = 90.0 degrees;
    // 1.375 us more is 0.133 degrees more.
    const double pulse = truth_value(rig.parts, "pan.pulse_us");
    EXPECT_NEAR(pulse, 1472.0 + 1.375, 0.01);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), (pulse - 544.0) / 1856.0 * 180.0, 1e-9);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), 90.0, 0.14);
}

TEST(Servo, TurnsAtItsSlewRateToTheEndStop) {
    // From 90 degrees at power-on toward 0 (544 us) at 600 deg/s. The
    // fixture's first pulse starts when Timer1 first reaches 40000 ticks
    // (20 ms) and ends 545.4 us later: the horn starts turning then. At
    // 100.0625 ms (the request at 62.5 us, then 100 ms) it has turned
    // 600 x (100.0625 - 20.545) ms = 47.7 degrees: it stands at 42.3.
    ServoRig rig(kServo);
    rig.send_us(544);
    rig.run_ms(100);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), 90.0 - 600.0 * (100.0625 - 20.545) * 1e-3, 0.2);
    rig.run_ms(100);  // 150 ms of turning are over: at the end stop (0.133 for the fixture's 1.375 us)
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), 0.133, 0.01);
    // Beyond the end stops: clamped.
    rig.send_us(2600);
    rig.run_ms(400);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), 180.0, 1e-9);
}

TEST(Servo, IgnoresChangesInsideItsDeadBandAndHoldsWhenThePulsesStop) {
    ServoRig rig(kServo);
    rig.send_us(1472);
    rig.run_ms(60);
    const double held = truth_value(rig.parts, "pan.angle_deg");
    rig.send_us(1477);  // 5 us: inside the 10 us dead band
    rig.run_ms(60);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "pan.angle_deg"), held);
    rig.send_us(0);  // no more pulses
    rig.run_ms(100);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "pan.angle_deg"), held);
}

TEST(Servo, FollowsPulsesFromATimersCompareOutput) {
    // OC1A in fast PWM, TOP = ICR1 = 39999 at /8: a 20 ms period, high for
    // OCR1A + 1 ticks of 8 cycles. 2400 us = 4800 ticks: OCR1A = 4799, the
    // width exactly 2400 us: 180 degrees after (180 - 90) / 600 s = 150 ms.
    ServoRig rig(kServo, nullptr, "servo_fixture_oc");
    rig.send_us(2400);
    rig.step_ms(200);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "pan.pulse_us"), 2400.0);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "pan.angle_deg"), 180.0);
    // 1000 us: (1000 - 544) / 1856 x 180 = 44.224 degrees, 226 ms later.
    rig.send_us(1000);
    rig.step_ms(100);
    // Turning: OCR1A is double-buffered (updated at TOP), so the new width
    // starts up to one 20 ms period after the write, seen at the next 1 ms
    // step: 180 - 600 x (0.100 - 0.021 .. 0.100) degrees.
    const double turning = truth_value(rig.parts, "pan.angle_deg");
    EXPECT_GE(turning, 180.0 - 600.0 * 0.100);
    EXPECT_LE(turning, 180.0 - 600.0 * 0.079);
    rig.step_ms(200);
    EXPECT_DOUBLE_EQ(truth_value(rig.parts, "pan.pulse_us"), 1000.0);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), (1000.0 - 544.0) / 1856.0 * 180.0, 1e-9);
    // OC1A switched off: no pulses, the horn holds.
    rig.send_us(0);
    rig.step_ms(100);
    EXPECT_NEAR(truth_value(rig.parts, "pan.angle_deg"), (1000.0 - 544.0) / 1856.0 * 180.0, 1e-9);
}

/// A wall along y = 0.10 m, 0.1 m to the robot's left: an FC-51 module set to
/// 15 cm sees it only when it looks left.
plant::World wall_on_the_left() {
    plant::World w;
    w.walls.push_back(plant::Wall{{-1.0, 0.10}, {1.0, 0.10}, 0.2});
    return w;
}

TEST(Servo, ASensorOnTheHornTurnsWithIt) {
    // The IR module sits on the horn at (60 mm, 0). At 90 degrees it looks
    // ahead: its 35-degree cone reaches y = 0.15 sin 17.5 = 0.045 m < 0.10
    // within its 15 cm: nothing. At 180 degrees (2400 us) it looks left: the
    // wall is 0.10 m away. At 0 degrees (544 us) it looks right: nothing.
    const plant::World world = wall_on_the_left();
    ServoRig rig(kServo + "  - {name: ir, type: ir-obstacle, OUT: 7, range_cm: 15, mount: pan}\n", &world);
    const auto detected_after = [&rig](double us) {
        rig.send_us(us);
        rig.run_ms(400);  // 180 degrees at 600 deg/s: 0.3 s, plus the 20 ms frame
        rig.parts.on_plant_step(rig.fx.core.cycle());
        return truth_value(rig.parts, "ir.detected");
    };
    rig.parts.on_plant_step(rig.fx.core.cycle());
    EXPECT_EQ(truth_value(rig.parts, "ir.detected"), 0.0);
    EXPECT_EQ(detected_after(2400), 1.0);
    EXPECT_EQ(detected_after(544), 0.0);
    EXPECT_EQ(detected_after(2400), 1.0);
}

TEST(Servo, APartOnTheHornIsCheckedWhenTheBoardFileIsRead) {
    const std::string head = "board: uno\nparts:\n  - {name: pan, type: servo, SIGNAL: 9}\n";
    const std::string& wheels = kUnoTestWheels;
    EXPECT_EQ(board_load_error(head + "  - {name: ir, type: ir-obstacle, OUT: 7, mount: pan}\n" + wheels), "");
    EXPECT_NE(board_load_error(head + "  - {name: ir, type: ir-obstacle, OUT: 7, mount: tilt}\n" + wheels)
                  .find("b.yaml:4: key 'parts.ir.mount': no part is called 'tilt'"),
              std::string::npos);
    EXPECT_NE(board_load_error(head + "  - {name: ir, type: ir-obstacle, OUT: 7}\n"
                                      "  - {name: ir2, type: ir-obstacle, OUT: 8, mount: ir}\n" + wheels)
                  .find("b.yaml:5: key 'parts.ir2.mount': part 'ir' (ir-obstacle) carries nothing"),
              std::string::npos);
    EXPECT_NE(board_load_error(head + "  - {name: sonar, type: ultrasonic, TRIG: 7, ECHO: 8, x_mm: 50, mount: pan}\n" + wheels)
                  .find("b.yaml:4: key 'parts.sonar.x_mm': not with mount: pan"),
              std::string::npos);
}

}  // namespace
}  // namespace ddmr::test
