// The MPU-6050 part, read register by register by a fixture master as
// i2cdevlib does (tests/firmware/imu_fixture.c), each value worked out by
// hand from the register map (hil/parts/imu_mpu6050.cpp).
#include <gtest/gtest.h>

#include <optional>

#include <cstdint>

#include "hil/cycle_time.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/board_file.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"

namespace ddmr::test {
namespace {

/// The robot turning on the spot at `rate_dps`; the plant stepped every
/// 1000 cycles (62.5 us) as the coupler does.
struct ImuRig {
    TempDir dir;
    FixtureCore fx{"imu_fixture"};
    double rate_dps = 0.0;
    hil::Cycles pose_cycle = 0;
    hil::PartSet parts;
    explicit ImuRig(const std::string& keys)
        : parts(fx.core, uno_with_parts(dir, "  - {name: imu, type: imu, SDA: A4, SCL: A5" + keys + "}\n").parts,
                hil::PartRegistry::global(), [this] {
                    const double t = hil::cycles_to_s(pose_cycle, fx.core.clock_hz());
                    return plant::Pose{0.0, 0.0, rate_dps * t * 3.14159265358979323846 / 180.0};
                }) {}
    void run_ms(double ms) {
        const hil::Cycles end = fx.core.cycle() + hil::ms_to_cycles(ms, fx.core.clock_hz());
        while (fx.core.cycle() < end) {
            pose_cycle = fx.core.cycle() + 1000;
            parts.on_plant_step(pose_cycle);
            fx.core.run_until(pose_cycle);
        }
    }
    [[nodiscard]] int16_t gyro(int axis) const {
        return static_cast<int16_t>(fx.u8("gyro", 2 * axis) << 8 | fx.u8("gyro", 2 * axis + 1));
    }
};

constexpr const char* kQuiet = ", gyro_noise_dps: 0, accel_noise_g: 0";

TEST(ImuMpu6050, AnswersWhoAmIAndReadsTheYawRateAt131LsbPerDegreePerSecond) {
    // 30 deg/s at FS_SEL 0 (+-250 deg/s): 30 x 131 = 3930 LSB on GYRO_ZOUT;
    // none on X and Y (a turn about the vertical only).
    ImuRig rig(kQuiet);
    rig.rate_dps = 30.0;
    rig.run_ms(100);
    EXPECT_EQ(rig.fx.u8("who"), 0x68);
    EXPECT_GT(rig.fx.u8("reads"), 5);
    EXPECT_EQ(rig.gyro(2), 3930);
    EXPECT_EQ(rig.gyro(0), 0);
    EXPECT_EQ(rig.gyro(1), 0);
    // FS_SEL 1 (+-500 deg/s): 65.5 LSB per deg/s: 1965.
    rig.fx.poke("fs_sel", 1);
    rig.run_ms(20);
    EXPECT_EQ(rig.gyro(2), 1965);
}

TEST(ImuMpu6050, UpsideDownFlipsTheYawRateAndTheBiasAdds) {
    // z_axis down: the chip's Z points at the floor, -30 deg/s; a 2 deg/s
    // bias on each axis: (-30 + 2) x 131 = -3668.
    ImuRig rig(std::string(kQuiet) + ", z_axis: down, gyro_bias_dps: 2");
    rig.rate_dps = 30.0;
    rig.run_ms(100);
    EXPECT_EQ(rig.gyro(2), -3668);
    EXPECT_EQ(rig.gyro(0), 262);  // 2 x 131
}

TEST(ImuMpu6050, AHeldYawRateReplacesTheTurnUntilReleased) {
    // Held at -100 deg/s while the robot turns at +30: -100 x 131 = -13100;
    // released: the turn's 3930 again (after the DLPF settles).
    ImuRig rig(kQuiet);
    rig.rate_dps = 30.0;
    rig.parts.set_reading("imu", "gyro_z_dps", -100.0);
    rig.run_ms(100);
    EXPECT_EQ(rig.gyro(2), -13100);
    EXPECT_EQ(rig.gyro(0), 0);
    rig.parts.set_reading("imu", "gyro_z_dps", std::nullopt);
    rig.run_ms(100);
    EXPECT_EQ(rig.gyro(2), 3930);
}

TEST(ImuMpu6050, AsleepAtResetItsRegistersStayZero) {
    // The fixture wakes it: before that (PWR_MGMT_1 = 0x40 at reset) nothing is sampled.
    ImuRig rig(kQuiet);
    rig.rate_dps = 30.0;
    rig.run_ms(0.1);
    EXPECT_EQ(truth_value(rig.parts, "imu.samples"), 0.0);
    rig.run_ms(50);
    // Due 8000 times a second (DLPF_CFG 0), each published when the bus is
    // next idle: at the fixture's STOPs, about 3 every 1.2 ms loop.
    EXPECT_GT(truth_value(rig.parts, "imu.samples"), 30.0);
}

TEST(ImuMpu6050, TheFifoIsWarnedAboutOnce) {
    ImuRig rig(kQuiet);
    rig.run_ms(10);
    EXPECT_TRUE(rig.parts.warnings().empty());
    rig.fx.poke("touch_fifo", 1);
    rig.run_ms(20);
    const auto w = rig.parts.warnings();
    ASSERT_EQ(w.size(), 1U);
    EXPECT_NE(w[0].find("part 'imu': the firmware written MPU-6050 register 0x6A"), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("the DMP and the FIFO are not modelled"), std::string::npos) << w[0];
}

TEST(ImuMpu6050, OffTheTwiPinsIsRefusedWithFileLine) {
    const std::string& wheels = kUnoTestWheels;
    const std::string error =
        board_load_error("board: uno\nparts:\n  - {name: imu, type: imu, SDA: 7, SCL: A5}\n" + wheels);
    EXPECT_NE(error.find("b.yaml:3: key 'parts.imu.SDA': '7' is not the"), std::string::npos) << error;
    EXPECT_NE(error.find("TWI SDA pin: the MPU-6050's SDA must be on A4 (PC4)"), std::string::npos) << error;
}

}  // namespace
}  // namespace ddmr::test
