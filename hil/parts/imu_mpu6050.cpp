// MPU-6050 (GY-521 boards) on the I2C bus (../shared/SENSORS.md section 5;
// InvenSense RM-MPU-6000A-00 rev. 4.2 [RM], PS-MPU-6000A-00 rev. 3.4 [PS]):
//   - a TwiSlave at 0x68 (AD0 low) or 0x69: ACK/NACK, auto-increment, repeated
//     START, and a register pointer that survives a STOP (hil/twi_slave.hpp);
//   - reset values 0 except PWR_MGMT_1 0x40 (asleep) and WHO_AM_I 0x68 ([RM]
//     section 3); DEVICE_RESET (0x6B bit 7) restores them and clears itself;
//   - asleep (PWR_MGMT_1 bit 6), the sensor registers keep their values;
//   - awake, a new sample at the sample rate, gyro output rate / (1 +
//     SMPLRT_DIV) (8 kHz with DLPF_CFG 0 or 7, else 1 kHz, [RM] 4.2); the
//     values pass a first-order low-pass at the DLPF's bandwidth (CONFIG
//     DLPF_CFG, [RM] 4.3) and are written to ACCEL/TEMP/GYRO_*OUT (big-endian
//     two's complement, scaled by GYRO_CONFIG FS_SEL: 131/65.5/32.8/16.4
//     LSB per deg/s, ACCEL_CONFIG AFS_SEL: 16384..2048 LSB/g; [RM] 4.17-4.19)
//     only while the bus is idle, so one burst read sees one sample ([RM]
//     4.17: a sample due during a transaction is written at its STOP, or at
//     the next plant step with the bus idle); INT_STATUS DATA_RDY is set per sample and cleared by reading it;
//   - the values: the robot's motion at the chip (plant/imu_kinematics.hpp),
//     plus gyro_bias_dps on each gyro axis, plus white noise of
//     gyro_noise_dps and accel_noise_g RMS per sample from a generator seeded
//     by `seed` ([PS] 6.1: 0.05 deg/s RMS total noise; 6.2: 400 ug/sqrt(Hz));
//     TEMP_OUT = (temperature_c - 36.53) x 340 ([RM] 4.18);
//   - the DMP and the FIFO are not modelled: a write to USER_CTRL's FIFO_EN or
//     DMP bits, FIFO_EN, the DMP's bank/memory registers (0x6D-0x71) or the
//     FIFO (0x72-0x74), or a read of the FIFO, gets one warning naming them.
// Not modelled: the INT pin, self-test, the auxiliary I2C master, motion
// detection (its registers are stored), sensitivity and cross-axis errors.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <optional>
#include <random>
#include <set>

#include "hil/cycle_time.hpp"
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"
#include "hil/twi_slave.hpp"
#include "plant/imu_kinematics.hpp"
#include "plant/units.hpp"

namespace ddmr::hil {
namespace {

namespace reg {
constexpr uint8_t kSmplrtDiv = 0x19, kConfig = 0x1A, kGyroConfig = 0x1B, kAccelConfig = 0x1C, kFifoEn = 0x23;
constexpr uint8_t kIntStatus = 0x3A, kAccelXoutH = 0x3B, kTempOutH = 0x41, kGyroXoutH = 0x43;
constexpr uint8_t kUserCtrl = 0x6A, kPwrMgmt1 = 0x6B, kDmpFirst = 0x6D, kFifoLast = 0x74, kWhoAmI = 0x75;
}  // namespace reg
constexpr uint8_t kDeviceReset = 0x80, kSleep = 0x40, kDataRdy = 0x01;
constexpr uint8_t kUserCtrlDmpFifo = 0xC0 | 0x08 | 0x04;  // DMP_EN, FIFO_EN, DMP_RESET, FIFO_RESET
/// DLPF_CFG 0..7 -> gyro bandwidth [Hz] ([RM] 4.3; 7 reserved: taken as 0's).
constexpr std::array<double, 8> kGyroBandwidthHz = {256, 188, 98, 42, 20, 10, 5, 256};
constexpr std::array<double, 8> kAccelBandwidthHz = {260, 184, 94, 44, 21, 10, 5, 260};
constexpr std::array<double, 4> kGyroLsbPerDps = {131.0, 65.5, 32.8, 16.4};
constexpr std::array<double, 4> kAccelLsbPerG = {16384.0, 8192.0, 4096.0, 2048.0};

int16_t saturate(double v) { return static_cast<int16_t>(std::clamp(std::lround(v), -32768L, 32767L)); }

class ImuMpu6050 final : public Part {
public:
    explicit ImuMpu6050(const PartContext& ctx)
        : core_(ctx.core()), pose_(ctx.pose_source()),
          twi_(ctx.core(), ctx.text("AD0") == "high" ? 0x69 : 0x68), mount_(mount_of(ctx)),
          bias_dps_(ctx.number("gyro_bias_dps")), gyro_noise_dps_(ctx.number("gyro_noise_dps")),
          accel_noise_g_(ctx.number("accel_noise_g")), temperature_c_(ctx.number("temperature_c")),
          rng_(static_cast<uint64_t>(ctx.number("seed"))), none_(ctx.name()) {
        reset_registers();
        twi_.set_write_listener([this](uint8_t r, uint8_t v) { on_write(r, v); });
        twi_.set_read_listener([this](uint8_t r) { on_read(r); });
        twi_.set_idle_listener([this] {
            if (pending_) publish();
        });
        const plant::Pose p = pose_();
        poses_ = {p, p, p};
    }

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"gyro_z_dps", "accel_x_g", "samples"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(filtered_.gyro_rad_s.z() * 180.0 / plant::kPi);
        out.push_back(filtered_.accel_m_s2.x() / plant::kStandardGravity_m_s2);
        out.push_back(static_cast<double>(samples_));
    }
    std::vector<std::string> warnings() const override { return warnings_; }
    void set_reading(const std::string& /*name*/, std::optional<double> value) override { held_z_dps_ = value; }

    void on_plant_step(Cycles pose_cycle) override {
        const double dt = cycles_to_s(pose_cycle - last_cycle_, core_.clock_hz());
        if (dt <= 0.0) return;
        poses_ = {poses_[1], poses_[2], pose_()};
        last_cycle_ = pose_cycle;
        if (!primed_) {  // the first step: no motion history yet
            primed_ = true;
            return;
        }
        plant::ImuReading raw = plant::imu_reading(poses_[0], poses_[1], poses_[2], dt, mount_);
        if (held_z_dps_) raw.gyro_rad_s.z() = *held_z_dps_ * plant::kPi / 180.0;  // before the DLPF, as the chip's rate
        filter(raw, dt);
        if (asleep()) return;
        if (pose_cycle >= next_sample_) {
            next_sample_ = pose_cycle + sample_period();
            pending_ = true;
        }
        if (pending_ && !twi_.in_transaction()) publish();
    }

private:
    static plant::ImuMount mount_of(const PartContext& ctx) {
        plant::ImuMount m;
        m.x_m = ctx.number("x_mm") * 1e-3;
        m.y_m = ctx.number("y_mm") * 1e-3;
        m.yaw_rad = ctx.number("yaw_deg") * plant::kPi / 180.0;
        m.z_down = ctx.text("z_axis") == "down";
        return m;
    }
    [[nodiscard]] bool asleep() const { return (twi_.reg(reg::kPwrMgmt1) & kSleep) != 0; }
    [[nodiscard]] uint8_t dlpf() const { return twi_.reg(reg::kConfig) & 0x07; }
    [[nodiscard]] Cycles sample_period() const {
        const double gyro_rate_hz = dlpf() == 0 || dlpf() == 7 ? 8000.0 : 1000.0;
        return s_to_cycles((1.0 + twi_.reg(reg::kSmplrtDiv)) / gyro_rate_hz, core_.clock_hz());
    }

    void reset_registers() {
        for (int r = 0; r < 256; ++r) twi_.set_reg(static_cast<uint8_t>(r), 0);
        twi_.set_reg(reg::kPwrMgmt1, kSleep);
        twi_.set_reg(reg::kWhoAmI, 0x68);
    }

    /// The DLPF: a first-order low-pass at the configured bandwidth.
    void filter(const plant::ImuReading& raw, double dt) {
        const double kg = 1.0 - std::exp(-2.0 * plant::kPi * kGyroBandwidthHz[dlpf()] * dt);
        const double ka = 1.0 - std::exp(-2.0 * plant::kPi * kAccelBandwidthHz[dlpf()] * dt);
        filtered_.gyro_rad_s += kg * (raw.gyro_rad_s - filtered_.gyro_rad_s);
        filtered_.accel_m_s2 += ka * (raw.accel_m_s2 - filtered_.accel_m_s2);
    }

    void put16(uint8_t at, int16_t v) {
        twi_.set_reg(at, static_cast<uint8_t>(static_cast<uint16_t>(v) >> 8));
        twi_.set_reg(static_cast<uint8_t>(at + 1), static_cast<uint8_t>(static_cast<uint16_t>(v) & 0xFF));
    }

    void publish() {
        pending_ = false;
        ++samples_;
        const double gyro_lsb = kGyroLsbPerDps[(twi_.reg(reg::kGyroConfig) >> 3) & 3];
        const double accel_lsb = kAccelLsbPerG[(twi_.reg(reg::kAccelConfig) >> 3) & 3];
        std::normal_distribution<double> unit(0.0, 1.0);
        for (int i = 0; i < 3; ++i) {
            const double dps = filtered_.gyro_rad_s[i] * 180.0 / plant::kPi + bias_dps_ + gyro_noise_dps_ * unit(rng_);
            put16(static_cast<uint8_t>(reg::kGyroXoutH + 2 * i), saturate(dps * gyro_lsb));
            const double g = filtered_.accel_m_s2[i] / plant::kStandardGravity_m_s2 + accel_noise_g_ * unit(rng_);
            put16(static_cast<uint8_t>(reg::kAccelXoutH + 2 * i), saturate(g * accel_lsb));
        }
        put16(reg::kTempOutH, saturate((temperature_c_ - 36.53) * 340.0));
        twi_.set_reg(reg::kIntStatus, static_cast<uint8_t>(twi_.reg(reg::kIntStatus) | kDataRdy));
    }

    void on_write(uint8_t r, uint8_t v) {
        if (r == reg::kPwrMgmt1 && (v & kDeviceReset) != 0) {
            reset_registers();  // DEVICE_RESET restores the defaults and clears itself ([RM] 4.28)
            return;
        }
        if (r == reg::kWhoAmI) twi_.set_reg(r, 0x68);  // read-only
        if ((r == reg::kUserCtrl && (v & kUserCtrlDmpFifo) != 0) || (r == reg::kFifoEn && v != 0) ||
            (r >= reg::kDmpFirst && r <= reg::kFifoLast)) {
            warn(r, "written");
        }
    }
    void on_read(uint8_t r) {
        if (r == reg::kIntStatus) twi_.set_reg(r, 0);  // INT_STATUS clears when read ([RM] 4.16)
        if (r >= 0x72 && r <= reg::kFifoLast) warn(r, "read");
    }
    void warn(uint8_t r, const char* how) {
        if (!warned_.insert(r).second || !warnings_.empty()) return;  // one warning, naming the first register
        warnings_.push_back(fmt::format(
            "the firmware {} MPU-6050 register 0x{:02X} at {:.4f} s: the DMP and the FIFO are not modelled "
            "(USER_CTRL FIFO_EN/DMP_EN, FIFO_EN 0x23, 0x6D-0x71 DMP, 0x72-0x74 FIFO); a sketch using them reads zeros",
            how, r, core_.seconds()));
    }

    AvrCore& core_;
    std::function<plant::Pose()> pose_;
    TwiSlave twi_;
    plant::ImuMount mount_;
    double bias_dps_, gyro_noise_dps_, accel_noise_g_, temperature_c_;
    std::optional<double> held_z_dps_;  ///< set_reading's rate about the chip's Z
    std::mt19937_64 rng_;
    DrivenSignal none_;
    std::array<plant::Pose, 3> poses_{};
    Cycles last_cycle_ = 0;
    bool primed_ = false;
    plant::ImuReading filtered_{};
    Cycles next_sample_ = 0;
    bool pending_ = false;
    uint64_t samples_ = 0;
    std::set<uint8_t> warned_;
    std::vector<std::string> warnings_;
};

/// The board's name of the pin at port bit `bit` ("A4", "20").
std::string twi_pin_name(const BoardDescription& board, PortBit bit) {
    for (int n = 0; n < board.pin_count(); ++n) {
        const PortBit& b = board.pins[static_cast<std::size_t>(n)];
        if (b.port == bit.port && b.bit == bit.bit) return sketch_pin_name(board, n);
    }
    return "none";
}

std::optional<PartKeyProblem> check(const PartEntry& e, const BoardDescription& board) {
    for (const auto& [key, bit] : {std::pair{"SDA", board.mcu->twi_sda}, std::pair{"SCL", board.mcu->twi_scl}}) {
        const int pin = e.values.at(key).pin;
        const PortBit at = pin >= 0 ? board.pins[static_cast<std::size_t>(pin)] : PortBit{};
        if (pin < 0 || at.port != bit.port || at.bit != bit.bit) {
            return PartKeyProblem{key, fmt::format("'{}' is not the {}'s TWI {} pin: the MPU-6050's {} must be on {} (P{}{})",
                                                   e.values.at(key).text, board.label, key, key,
                                                   twi_pin_name(board, bit), bit.port, static_cast<int>(bit.bit))};
        }
    }
    return std::nullopt;
}

}  // namespace

PartType imu_mpu6050_type() {
    PartType t;
    t.type = "imu";
    t.readings = {{"gyro_z_dps", "the rate about the chip's Z axis [deg/s], in place of the robot's turn (then the "
                                 "DLPF, the bias and the noise, as the motion's)",
                   -2000.0, 2000.0}};
    t.summary = "MPU-6050 (GY-521) on the I2C bus: gyro, accelerometer and temperature registers from the robot's motion";
    t.datasheet = "InvenSense RM-MPU-6000A-00 rev. 4.2 (register map), PS-MPU-6000A-00 rev. 3.4 (scales, noise)";
    t.keys = {PartKey::input("SDA", "the I2C data line: the board's TWI SDA pin (Uno A4, Mega 20)"),
              PartKey::input("SCL", "the I2C clock line: the board's TWI SCL pin (Uno A5, Mega 21)"),
              PartKey::choice("AD0", "the address pin: low 0x68, high 0x69", {"low", "high"})};
    for (PartKey& k : mount_keys("the chip's", false, 0)) t.keys.push_back(std::move(k));
    t.keys.push_back(PartKey::number("yaw_deg", "the chip's X axis, counter-clockwise from forward [deg]", 0, -180, 180));
    t.keys.push_back(PartKey::choice("z_axis", "up, or down for a board mounted upside down (Y and Z flip)", {"up", "down"}));
    t.keys.push_back(PartKey::number("gyro_bias_dps", "a bias added to each gyro axis [deg/s] (PS 6.1: up to 20)", 0, -250, 250));
    t.keys.push_back(PartKey::number("gyro_noise_dps", "white noise on each gyro sample, RMS [deg/s]", 0.05, 0, 50));
    t.keys.push_back(PartKey::number("accel_noise_g", "white noise on each accelerometer sample, RMS [g]", 0.004, 0, 1));
    t.keys.push_back(PartKey::number("temperature_c", "the die temperature TEMP_OUT reports [degC]", 25, -40, 85));
    t.keys.push_back(PartKey::number("seed", "the noise generator's seed", 1, 0, 4294967295.0));
    t.create = [](const PartContext& ctx) { return std::make_unique<ImuMpu6050>(ctx); };
    t.check = check;
    return t;
}

}  // namespace ddmr::hil
