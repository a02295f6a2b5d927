// Tests for plant/l298_driver: terminal conditions of the two input models
// (drop 1.4 V, diode 0.8 V, battery 6.1 V unless stated).
#include "plant/l298_driver.hpp"

#include <gtest/gtest.h>

namespace ddmr::plant {
namespace {

TEST(L298, AveragedModelIsDutyTimesAvailableVoltage) {
    const L298Params p;
    // 0.5 x (6.1 - 1.4) = 2.35 V forward, -2.35 V reverse.
    MotorTerminal t = terminal(p, DriveMode::averaged, BridgeInput{false, 0.5, true}, 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::driven);
    EXPECT_NEAR(t.voltage_V, 2.35, 1e-12);
    EXPECT_NEAR(t.supply_factor, 0.5, 1e-12);
    t = terminal(p, DriveMode::averaged, BridgeInput{false, 0.5, false}, 6.1);
    EXPECT_NEAR(t.voltage_V, -2.35, 1e-12);
    EXPECT_NEAR(t.supply_factor, -0.5, 1e-12);
}

TEST(L298, SwitchedModelFollowsTheEnablePin) {
    const L298Params p;
    // Enabled: the full 6.1 - 1.4 = 4.7 V whatever the duty field says.
    MotorTerminal t = terminal(p, DriveMode::switched, BridgeInput{true, 0.1, true}, 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::driven);
    EXPECT_NEAR(t.voltage_V, 4.7, 1e-12);
    t = terminal(p, DriveMode::switched, BridgeInput{true, 0.1, false}, 6.1);
    EXPECT_NEAR(t.voltage_V, -4.7, 1e-12);
    // Disabled: bridge off, clamp = 6.1 + 2 x 0.8 = 7.7 V.
    t = terminal(p, DriveMode::switched, BridgeInput{false, 0.9, true}, 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::open);
    EXPECT_NEAR(t.clamp_V, 7.7, 1e-12);
}

TEST(L298, BatteryResistanceAppearsInSeriesScaledByDutySquared) {
    const L298Params p;
    // Averaged: V_term = D (V_src - R_b D I - drop) = D (V_src - drop) - D^2 R_b I,
    // so the motor sees R_s = 0.5^2 x 0.037 = 0.00925 ohm in series.
    MotorTerminal t = terminal(p, DriveMode::averaged, BridgeInput{false, 0.5, true}, 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.00925, 1e-15);
    // Switched, enabled or freewheeling: the whole R_b.
    t = terminal(p, DriveMode::switched, BridgeInput{true, 0.5, false}, 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.037, 1e-15);
    t = terminal(p, DriveMode::switched, BridgeInput{false, 0.5, true}, 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.037, 1e-15);
}

TEST(L298, NothingPassesBelowTheDrop) {
    const MotorTerminal t =
        terminal(L298Params{}, DriveMode::switched, BridgeInput{true, 1.0, true}, 1.0);
    EXPECT_EQ(t.voltage_V, 0.0);  // 1.0 V battery < 1.4 V drop
}

}  // namespace
}  // namespace ddmr::plant
