// step_across_edges: the one plant stepper (plant/drive_stepper.hpp).
#include "plant/drive_stepper.hpp"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include "plant/robot_params.hpp"

namespace ddmr::plant {
namespace {

constexpr std::uint32_t kClockHz = 16'000'000;

/// Motor 0 forward until cycle 100, coast until 250, forward after; motor 1
/// coast until 200, reverse after: changes at 100, 200 and 250.
class ScriptedWaves final : public DriveWaveforms {
public:
    BridgeState state_at(std::size_t m, std::int64_t c) const override {
        if (m == 0) return c < 100 || c >= 250 ? BridgeState::forward : BridgeState::coast;
        return c < 200 ? BridgeState::coast : BridgeState::reverse;
    }
    std::int64_t next_change_after(std::size_t m, std::int64_t c) const override {
        if (m == 0) return c < 100 ? 100 : c < 250 ? 250 : kNever;
        return c < 200 ? 200 : kNever;
    }
};

RobotInput full_drive(DriveMode mode) {
    RobotInput in;
    in.mode = mode;
    for (auto& b : in.bridge) {
        b.duty = 1.0;
        b.forward = true;
    }
    return in;
}

TEST(DriveStepper, SwitchedModeSplitsAtEveryChangeWithTheStatesOfEachPiece) {
    Robot robot(default_robot_params());
    RobotInput in = full_drive(DriveMode::switched);
    EdgeBuffer edges;
    std::vector<std::pair<std::int64_t, std::pair<BridgeState, BridgeState>>> pieces;
    const DriveStepResult r = step_across_edges(
        robot, in, ScriptedWaves{}, 0, 1000, kClockHz, edges, [&](std::int64_t start, const EdgeBuffer&) {
            pieces.push_back({start, {robot.input().bridge[0].state, robot.input().bridge[1].state}});
        });
    EXPECT_EQ(r.status, StepStatus::ok);
    ASSERT_EQ(r.pieces, 4U);  // [0,100) [100,200) [200,250) [250,1000)
    ASSERT_EQ(pieces.size(), 4U);
    EXPECT_EQ(pieces[0].first, 0);
    EXPECT_EQ(pieces[1].first, 100);
    EXPECT_EQ(pieces[2].first, 200);
    EXPECT_EQ(pieces[3].first, 250);
    EXPECT_EQ(pieces[0].second, std::make_pair(BridgeState::forward, BridgeState::coast));
    EXPECT_EQ(pieces[1].second, std::make_pair(BridgeState::coast, BridgeState::coast));
    EXPECT_EQ(pieces[2].second, std::make_pair(BridgeState::coast, BridgeState::reverse));
    EXPECT_EQ(pieces[3].second, std::make_pair(BridgeState::forward, BridgeState::reverse));
    // 1000 cycles at 16 MHz = 62.5 us of plant time.
    EXPECT_DOUBLE_EQ(robot.time_s(), 1000.0 / kClockHz);
}

TEST(DriveStepper, AveragedModeIsOneStepWithTheInputAsGiven) {
    Robot robot(default_robot_params());
    RobotInput in = full_drive(DriveMode::averaged);
    in.bridge[0].state = BridgeState::brake;  // not the waveform's: averaged mode leaves it alone
    EdgeBuffer edges;
    const DriveStepResult r = step_across_edges(robot, in, ScriptedWaves{}, 0, 1000, kClockHz, edges);
    EXPECT_EQ(r.status, StepStatus::ok);
    EXPECT_EQ(r.pieces, 1U);
    EXPECT_EQ(robot.input().bridge[0].state, BridgeState::brake);
    EXPECT_DOUBLE_EQ(robot.time_s(), 1000.0 / kClockHz);
}

TEST(DriveStepper, StopsAtTheFirstPieceThatFails) {
    Robot robot(default_robot_params());
    RobotInput in = full_drive(DriveMode::switched);
    in.bridge[1].duty = 2.0;  // out of [0, 1]: bad input, nothing advances
    EdgeBuffer edges;
    int calls = 0;
    const DriveStepResult r = step_across_edges(robot, in, ScriptedWaves{}, 0, 1000, kClockHz, edges,
                                                [&](std::int64_t, const EdgeBuffer&) { ++calls; });
    EXPECT_EQ(r.status, StepStatus::bad_input);
    EXPECT_EQ(r.pieces, 1U);
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(robot.time_s(), 0.0);
}

TEST(DriveStepper, PwmDriveSwitchesTheEnableOnTheAnalogWriteWaveform) {
    // OCR 128 on the 32,640-cycle phase-correct period: high for 2 x 128 x 64
    // = 16,384 cycles centred on BOTTOM (cycle 0): falls at 8,192, rises at
    // 32,640 - 8,192 = 24,448.
    PwmDrive drive;
    drive.pwm[0].ocr = 128;
    drive.forward[0] = false;
    EXPECT_EQ(drive.state_at(0, 0), BridgeState::reverse);
    EXPECT_EQ(drive.next_change_after(0, 0), 8192);
    EXPECT_EQ(drive.state_at(0, 8192), BridgeState::coast);
    EXPECT_EQ(drive.next_change_after(0, 8192), 24448);
    EXPECT_EQ(drive.state_at(1, 0), BridgeState::coast);  // OCR 0: always low
    EXPECT_EQ(drive.next_change_after(1, 0), DriveWaveforms::kNever);
}

}  // namespace
}  // namespace ddmr::plant
