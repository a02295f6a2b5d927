// One trivial test part per capability a part has at run time, each
// registered from this file, wired by a board file and run on a fixture
// firmware: what the sensors of docs/parts_capabilities.md stand on.
//   test-pull-up-watch  a pin's mode and pull-up (PinProbe, PartContext::input_pin)
//   test-edge-at        an edge at an exact future cycle (PinDriver::schedule)
//   test-voltage        a voltage on an analog pin (AdcInput)
//   test-register-bank  a device on the TWI bus (TwiSlave)
//   test-pose-gate      the robot's pose after each plant step (Part::on_plant_step)
#include <gtest/gtest.h>

#include <fstream>

#include "hil/adc_input.hpp"
#include "hil/board.hpp"
#include "hil/cycle_time.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "hil/pin_driver.hpp"
#include "hil/pin_probe.hpp"
#include "hil/robot_rig.hpp"
#include "hil/twi_slave.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

/// PULLED: high while the firmware has the pull-up of PIN on (Table 13-1).
class PullUpWatch final : public hil::Part {
public:
    explicit PullUpWatch(const hil::PartContext& ctx)
        : probe_(ctx.core(), ctx.input_pin("PIN")), pulled_(ctx.name() + ".PULLED") {
        probe_.set_listener([this](const hil::PinState& s, hil::Cycles c) { pulled_.set(s.pull_up, c); });
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return pulled_; }
    std::vector<std::string> truth_columns() const override { return {"level"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(static_cast<double>(probe_.state().level));
    }

private:
    hil::PinProbe probe_;
    hil::DrivenSignal pulled_;
};

/// OUT low from power-on, high from exactly `at_us`.
class EdgeAt final : public hil::Part {
public:
    explicit EdgeAt(const hil::PartContext& ctx) : driver_(ctx.core()), edge_(ctx.name() + ".EDGE") {
        const int pin = ctx.output_pin("OUT");
        driver_.drive_now(pin, false);
        driver_.schedule(pin, hil::s_to_cycles(ctx.number("at_us") * 1e-6, ctx.core().clock_hz()), true);
        driver_.set_after_edge([this](int, hil::Cycles c, bool level) {
            edge_.set(level, c);
            edge_cycle_ = c;
        });
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return edge_; }
    std::vector<std::string> truth_columns() const override { return {"edge_cycle"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(static_cast<double>(edge_cycle_)); }

private:
    hil::PinDriver driver_;
    hil::DrivenSignal edge_;
    hil::Cycles edge_cycle_ = 0;
};

/// `volts` on analog pin OUT.
class Voltage final : public hil::Part {
public:
    explicit Voltage(const hil::PartContext& ctx) : adc_(ctx.core()), none_(ctx.name()) {
        adc_.set_voltage(ctx.output_pin("OUT"), ctx.number("volts"));
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"conversions"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(static_cast<double>(adc_.conversions())); }

private:
    hil::AdcInput adc_;
    hil::DrivenSignal none_;
};

/// A TWI device at `address` whose registers all start at `value`.
class RegisterBank final : public hil::Part {
public:
    explicit RegisterBank(const hil::PartContext& ctx)
        : slave_(ctx.core(), static_cast<int>(ctx.number("address"))), none_(ctx.name()) {
        for (int r = 0; r < 256; ++r) slave_.set_reg(static_cast<uint8_t>(r), static_cast<uint8_t>(ctx.number("value")));
        slave_.set_write_listener([this](uint8_t, uint8_t) { ++writes_; });
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"writes"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(static_cast<double>(writes_)); }

private:
    hil::TwiSlave slave_;
    hil::DrivenSignal none_;
    uint64_t writes_ = 0;
};

/// OUT goes high at the plant step whose pose is past x = `x_m`.
class PoseGate final : public hil::Part {
public:
    explicit PoseGate(const hil::PartContext& ctx)
        : pose_(ctx.pose_source()), pin_(ctx.output_pin("OUT")), x_m_(ctx.number("x_m")), driver_(ctx.core()),
          none_(ctx.name()) {
        driver_.drive_now(pin_, false);
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"steps", "x_m", "edge_cycle"}; }
    void truth_values(std::vector<double>& out) const override {
        out.push_back(static_cast<double>(steps_));
        out.push_back(x_seen_m_);
        out.push_back(static_cast<double>(edge_cycle_));
    }
    void on_plant_step(hil::Cycles pose_cycle) override {
        ++steps_;
        x_seen_m_ = pose_().x_m;
        if (edge_cycle_ == 0 && x_seen_m_ > x_m_) {
            driver_.schedule(pin_, pose_cycle, true);
            edge_cycle_ = pose_cycle;
        }
    }

private:
    std::function<plant::Pose()> pose_;
    int pin_;
    double x_m_;
    hil::PinDriver driver_;
    hil::DrivenSignal none_;
    uint64_t steps_ = 0;
    double x_seen_m_ = 0.0;
    hil::Cycles edge_cycle_ = 0;
};

/// OUT high while the floor under the robot's centre is darker than 0.5
/// (a one-spot line sensor); counts the times it went onto a line.
class FloorProbe final : public hil::Part {
public:
    explicit FloorProbe(const hil::PartContext& ctx)
        : pose_(ctx.pose_source()), world_(ctx.world()), pin_(ctx.output_pin("OUT")), driver_(ctx.core()), none_(ctx.name()) {
        driver_.drive_now(pin_, false);
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"lines_entered"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(static_cast<double>(entered_)); }
    void on_plant_step(hil::Cycles pose_cycle) override {
        const plant::Pose p = pose_();
        const bool dark = plant::reflectance_at(world_, {p.x_m, p.y_m}) < 0.5;
        if (dark == on_) return;
        on_ = dark;
        if (dark) ++entered_;
        driver_.schedule(pin_, pose_cycle, dark);
    }

private:
    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    int pin_;
    hil::PinDriver driver_;
    hil::DrivenSignal none_;
    bool on_ = false;
    uint64_t entered_ = 0;
};

template <typename P>
hil::PartType test_type(std::string word, std::vector<hil::PartKey> keys) {
    hil::PartType t;
    t.type = std::move(word);
    t.summary = "a test part";
    t.datasheet = "none: a test";
    t.keys = std::move(keys);
    t.create = [](const hil::PartContext& ctx) { return std::make_unique<P>(ctx); };
    return t;
}

void register_test_parts() {
    static const bool done = [] {
        hil::PartRegistry& r = hil::PartRegistry::global();
        hil::PartType watch = test_type<PullUpWatch>("test-pull-up-watch", {hil::PartKey::input("PIN", "the pin watched")});
        watch.ports = {{"PULLED", "high while the pin's pull-up is on"}};
        r.add(watch);
        hil::PartType edge = test_type<EdgeAt>("test-edge-at", {hil::PartKey::output("OUT", "the pin driven"),
                                                                 hil::PartKey::number("at_us", "edge time", 100, 0, 1e6)});
        edge.ports = {{"EDGE", "the level driven"}};
        r.add(edge);
        r.add(test_type<Voltage>("test-voltage", {hil::PartKey::output("OUT", "the analog pin"),
                                                  hil::PartKey::number("volts", "its voltage", 0, 0, 5)}));
        r.add(test_type<RegisterBank>("test-register-bank", {hil::PartKey::number("address", "7-bit", 0x68, 8, 0x77),
                                                             hil::PartKey::number("value", "registers", 0, 0, 255)}));
        r.add(test_type<FloorProbe>("test-floor-probe", {hil::PartKey::output("OUT", "the pin driven")}));
        r.add(test_type<PoseGate>("test-pose-gate", {hil::PartKey::output("OUT", "the pin driven"),
                                                     hil::PartKey::number("x_m", "the x it waits for", 0.01, 0, 10)}));
        return true;
    }();
    (void)done;
}

const std::string kWheels =
    "wheels:\n"
    "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n"
    "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 3}}\n";

/// The wheels with their encoders off D2 and D3.
const std::string kWheelsOff2 =
    "wheels:\n"
    "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 4}}\n"
    "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 5}}\n";

/// The board file `parts` (YAML list items) on an Uno, read back.
hil::BoardWiring board_with(const TempDir& dir, const std::string& parts, const std::string& wheels = kWheels) {
    register_test_parts();
    std::ofstream(dir / "b.yaml") << "board: uno\nparts:\n" << parts << wheels;
    return hil::load_board_file(dir / "b.yaml");
}

TEST(CapabilityParts, APartSeesThePinModeAndPullUp) {
    TempDir dir;
    FixtureCore fx{"pins_fixture"};
    const hil::PartSet parts(fx.core, board_with(dir, "  - {name: w, type: test-pull-up-watch, PIN: 7}\n").parts,
                             hil::PartRegistry::global(), [] { return plant::Pose{}; });
    const hil::LogicSignal& pulled = parts.output("w", "PULLED");
    const std::vector<std::pair<uint8_t, bool>> stages{{1, false}, {2, true}, {3, false}, {4, true}, {5, false}};
    for (const auto& [stage, pull_up] : stages) {
        ASSERT_TRUE(fx.handshake("stage", "done", stage, 20000)) << "stage " << int{stage};
        EXPECT_EQ(pulled.level_at(fx.core.cycle()), pull_up) << "stage " << int{stage};
    }
    EXPECT_EQ(truth_value(parts, "w.level"), static_cast<double>(hil::PinLevel::driven_high));  // stage 5
}

TEST(CapabilityParts, APartThatNeedsAPinRefusesAnInputWiredElsewhere) {
    TempDir dir;
    FixtureCore fx{"pins_fixture"};
    const hil::BoardWiring board = board_with(dir, "  - {name: w, type: test-pull-up-watch, PIN: high}\n");
    try {
        const hil::PartSet parts(fx.core, board.parts, hil::PartRegistry::global(), [] { return plant::Pose{}; });
        ADD_FAILURE() << "a pull-up watch on a constant was built";
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(), "part 'w' (test-pull-up-watch): key 'PIN' must be wired to a board pin, not 'high'");
    }
}

TEST(CapabilityParts, APartRaisesAnEdgeAtItsExactCycle) {
    TempDir dir;
    FixtureCore fx{"edge_fixture"};
    const hil::PartSet parts(fx.core, board_with(dir, "  - {name: e, type: test-edge-at, OUT: 2, at_us: 200}\n", kWheelsOff2).parts,
                             hil::PartRegistry::global(), [] { return plant::Pose{}; });
    const hil::Cycles at = 200 * 16;  // 200 us at 16 MHz
    fx.core.run_until(at - 50);
    EXPECT_EQ(fx.u16("int0_count"), 0);
    EXPECT_FALSE(parts.output("e", "EDGE").level_at(fx.core.cycle()));
    fx.core.run_until(at + 200);
    EXPECT_EQ(fx.u16("int0_count"), 1);  // INT0 on the rising edge of D2
    EXPECT_TRUE(parts.output("e", "EDGE").level_at(fx.core.cycle()));
    EXPECT_EQ(truth_value(parts, "e.edge_cycle"), static_cast<double>(at));
}

TEST(CapabilityParts, APartPutsAVoltageOnAnAnalogPin) {
    TempDir dir;
    FixtureCore fx{"adc_fixture"};
    const hil::PartSet parts(fx.core,
                             board_with(dir, "  - {name: a, type: test-voltage, OUT: A2, volts: 2.5}\n"
                                             "  - {name: b, type: test-voltage, OUT: A4, volts: 1.0}\n")
                                 .parts,
                             hil::PartRegistry::global(), [] { return plant::Pose{}; });
    ASSERT_TRUE(fx.run_until_u8("rounds", 2, hil::ms_to_cycles(20, fx.core.clock_hz())));
    EXPECT_EQ(fx.u16("codes", 2), 512);  // floor(2.5 V * 1024 / 5 V), section 24.7
    EXPECT_EQ(fx.u16("codes", 4), 204);  // floor(1.0 * 1024 / 5)
    EXPECT_GE(truth_value(parts, "a.conversions"), 1.0);
}

TEST(CapabilityParts, APartAnswersOnTheTwiBus) {
    TempDir dir;
    FixtureCore fx{"twi_fixture"};
    const hil::PartSet parts(fx.core,
                             board_with(dir, "  - {name: imu, type: test-register-bank, address: 0x68, value: 0x42}\n")
                                 .parts,
                             hil::PartRegistry::global(), [] { return plant::Pose{}; });
    ASSERT_TRUE(fx.run_until_u8("done", 1, hil::ms_to_cycles(50, fx.core.clock_hz())));
    EXPECT_EQ(fx.bytes("block", 6), std::vector<uint8_t>(6, 0x42));
    EXPECT_EQ(fx.bytes("readback", 2), (std::vector<uint8_t>{0xA5, 0x5A}));  // written, then read back
    EXPECT_EQ(truth_value(parts, "imu.writes"), 2.0);
}

TEST(CapabilityParts, APartSeesThePoseAfterEachPlantStep) {
    TempDir dir;
    hil::RigConfig config;
    config.board = board_with(dir, "  - {name: gate, type: test-pose-gate, OUT: 7, x_m: 0.005}\n");
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "drive_fixture.elf");
    hil::RobotRig rig(elf, config);  // drive_fixture: both motors forward at full drive
    const auto pind7 = [&rig] { return (rig.core().data(0x29) >> 7) & 1; };  // PIND bit 7
    rig.core().run_until(hil::ms_to_cycles(5, rig.core().clock_hz()));
    EXPECT_EQ(pind7(), 0);
    EXPECT_EQ(truth_value(rig.parts(), "gate.steps"), static_cast<double>(rig.coupler().steps()));
    rig.core().run_until(hil::ms_to_cycles(400, rig.core().clock_hz()));
    const double edge = truth_value(rig.parts(), "gate.edge_cycle");
    ASSERT_GT(edge, 0.0) << "the robot never passed x = 5 mm";
    EXPECT_EQ(pind7(), 1);
    EXPECT_EQ(truth_value(rig.parts(), "gate.steps"), static_cast<double>(rig.coupler().steps()));
    EXPECT_DOUBLE_EQ(truth_value(rig.parts(), "gate.x_m"), rig.robot().pose().x_m);
    EXPECT_GT(rig.robot().pose().x_m, 0.005);
}

TEST(CapabilityParts, APartSeesTheWorldUnderTheRobot) {
    TempDir dir;
    hil::RigConfig config;
    config.board = board_with(dir, "  - {name: probe, type: test-floor-probe, OUT: 7}\n");
    // A 19 mm tape across the path at x = 10 mm (dark from 0.5 to 19.5 mm),
    // the robot starting 10 mm behind the origin.
    config.world.lines.push_back(plant::FloorLine{{plant::LinePiece::segment({0.01, -1}, {0.01, 1})}});
    config.world.start = plant::Pose{-0.01, 0.0, 0.0};
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "drive_fixture.elf");
    hil::RobotRig rig(elf, config);
    EXPECT_EQ(rig.robot().pose().x_m, -0.01);  // the world's start
    const auto pind7 = [&rig] { return (rig.core().data(0x29) >> 7) & 1; };
    const auto x_when = [&rig, &pind7](int level) {
        for (int ms = 1; ms <= 2000; ++ms) {
            rig.core().run_until(hil::ms_to_cycles(ms, rig.core().clock_hz()));
            if (pind7() == level) return rig.robot().pose().x_m;
        }
        return -1.0;
    };
    const double on_at = x_when(1);
    EXPECT_GT(on_at, 0.0005);
    EXPECT_LT(on_at, 0.004);  // within a millisecond's travel of the tape's edge
    const double off_at = x_when(0);
    EXPECT_GT(off_at, 0.0195);
    EXPECT_LT(off_at, 0.023);
    EXPECT_EQ(truth_value(rig.parts(), "probe.lines_entered"), 1.0);
}

}  // namespace
}  // namespace ddmr::test
