// Tests for plant/bridge_driver: the terminal condition of each bridge state
// and of the averaged model, for the L298 (drop 1.4 V, diode 0.8 V), the
// L293D (drop 2.6 V, diode 1.3 V) and the MOSFET chips, battery 6.1 V unless
// stated.
#include "plant/bridge_driver.hpp"

#include <gtest/gtest.h>

namespace ddmr::plant {
namespace {

const BridgeParams kL298 = default_bridge_params(DriverChip::l298);
const BridgeParams kTb6612 = default_bridge_params(DriverChip::tb6612);
const BridgeParams kDrv8833 = default_bridge_params(DriverChip::drv8833);
const BridgeParams kL293d = default_bridge_params(DriverChip::l293d);

BridgeInput averaged(double duty, bool forward, double brake = 0.0) {
    BridgeInput in;
    in.duty = duty;
    in.forward = forward;
    in.brake = brake;
    return in;
}

BridgeInput switched(BridgeState s) {
    BridgeInput in;
    in.state = s;
    return in;
}

TEST(BridgeDriver, DefaultsPerChipAreTheDatasheetValues) {
    EXPECT_EQ(kL298.drop_V, 1.4);
    EXPECT_EQ(kL298.on_resistance_ohm, 0.0);
    EXPECT_EQ(kL298.brake_resistance_ohm, 0.0);
    EXPECT_EQ(kL298.flyback_diode_drop_V, 0.8);
    EXPECT_EQ(kTb6612.on_resistance_ohm, 0.5);    // Vsat(U+L) 0.5 V at 1 A
    EXPECT_EQ(kTb6612.brake_resistance_ohm, 0.5); // 2 x (0.5 / 2)
    EXPECT_EQ(kTb6612.flyback_diode_drop_V, 1.0);
    EXPECT_EQ(kDrv8833.on_resistance_ohm, 0.36);  // 200 + 160 mohm
    EXPECT_EQ(kDrv8833.brake_resistance_ohm, 0.32);  // 2 x 160 mohm
    EXPECT_EQ(kDrv8833.drop_V, 0.0);
    EXPECT_EQ(kL293d.drop_V, 2.6);                // VOH drop 1.4 + VOL 1.2 V typ at 0.6 A
    EXPECT_EQ(kL293d.on_resistance_ohm, 0.0);
    EXPECT_EQ(kL293d.brake_resistance_ohm, 0.0);  // fast motor stop as a short, as the L298's
    EXPECT_EQ(kL293d.flyback_diode_drop_V, 1.3);  // VOKH / VOKL typ at 0.6 A
}

TEST(BridgeDriver, AveragedModelIsDutyTimesAvailableVoltage) {
    // 0.5 x (6.1 - 1.4) = 2.35 V forward, -2.35 V reverse.
    MotorTerminal t = terminal(kL298, DriveMode::averaged, averaged(0.5, true), 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::driven);
    EXPECT_NEAR(t.voltage_V, 2.35, 1e-12);
    EXPECT_NEAR(t.supply_factor, 0.5, 1e-12);
    t = terminal(kL298, DriveMode::averaged, averaged(0.5, false), 6.1);
    EXPECT_NEAR(t.voltage_V, -2.35, 1e-12);
    EXPECT_NEAR(t.supply_factor, -0.5, 1e-12);
}

TEST(BridgeDriver, SwitchedModelFollowsTheBridgeState) {
    // Driving: the full 6.1 - 1.4 = 4.7 V whatever the duty field says.
    BridgeInput in = switched(BridgeState::forward);
    in.duty = 0.1;
    MotorTerminal t = terminal(kL298, DriveMode::switched, in, 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::driven);
    EXPECT_NEAR(t.voltage_V, 4.7, 1e-12);
    EXPECT_EQ(t.supply_factor, 1.0);
    t = terminal(kL298, DriveMode::switched, switched(BridgeState::reverse), 6.1);
    EXPECT_NEAR(t.voltage_V, -4.7, 1e-12);
    EXPECT_EQ(t.supply_factor, -1.0);
    // Coast: bridge off, clamp = 6.1 + 2 x 0.8 = 7.7 V.
    t = terminal(kL298, DriveMode::switched, switched(BridgeState::coast), 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::open);
    EXPECT_NEAR(t.clamp_V, 7.7, 1e-12);
    // Brake: a shorted winding; the battery sees nothing.
    t = terminal(kL298, DriveMode::switched, switched(BridgeState::brake), 6.1, 0.037);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::driven);
    EXPECT_EQ(t.voltage_V, 0.0);
    EXPECT_EQ(t.supply_factor, 0.0);
    EXPECT_EQ(t.series_resistance_ohm, 0.0);
}

TEST(BridgeDriver, BatteryResistanceAppearsInSeriesScaledByDutySquared) {
    // Averaged: V_term = D (V_src - R_b D I - drop) = D (V_src - drop) - D^2 R_b I,
    // so the motor sees R_s = 0.5^2 x 0.037 = 0.00925 ohm in series.
    MotorTerminal t = terminal(kL298, DriveMode::averaged, averaged(0.5, true), 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.00925, 1e-15);
    // Switched, driving or freewheeling: the whole R_b.
    t = terminal(kL298, DriveMode::switched, switched(BridgeState::reverse), 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.037, 1e-15);
    t = terminal(kL298, DriveMode::switched, switched(BridgeState::coast), 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.037, 1e-15);
}

TEST(BridgeDriver, WithoutBridgeResistanceTheSeriesTermIsUnchangedBitForBit) {
    // The L298 adds 0 ohm: D^2 R_b + D x 0 + brake x 0 must be D^2 R_b exactly.
    for (double d : {0.0, 0.2, 1.0 / 3.0, 0.5, 0.999, 1.0}) {
        const MotorTerminal t = terminal(kL298, DriveMode::averaged, averaged(d, true), 6.1, 0.037);
        EXPECT_EQ(t.series_resistance_ohm, d * d * 0.037) << d;
    }
    const MotorTerminal t = terminal(kL298, DriveMode::switched, switched(BridgeState::forward), 6.1, 0.037);
    EXPECT_EQ(t.series_resistance_ohm, 0.037);
}

TEST(BridgeDriver, MosfetBridgesAddTheirOnAndBrakeResistance) {
    // TB6612 driving: no drop, 6.1 V, R_on 0.5 ohm + R_b 0.037 ohm in series.
    MotorTerminal t = terminal(kTb6612, DriveMode::switched, switched(BridgeState::forward), 6.1, 0.037);
    EXPECT_EQ(t.voltage_V, 6.1);
    EXPECT_NEAR(t.series_resistance_ohm, 0.537, 1e-15);
    // DRV8833 braking: two low sides, 0.32 ohm, no battery share.
    t = terminal(kDrv8833, DriveMode::switched, switched(BridgeState::brake), 6.1, 0.037);
    EXPECT_EQ(t.series_resistance_ohm, 0.32);
    EXPECT_EQ(t.supply_factor, 0.0);
    // Coast through the TB6612's regenerative diodes: 6.1 + 2 x 1.0 = 8.1 V.
    t = terminal(kTb6612, DriveMode::switched, switched(BridgeState::coast), 6.1);
    EXPECT_NEAR(t.clamp_V, 8.1, 1e-12);
    // Averaged, 0.6 driving and 0.4 braking (TB6612 PWM mode), R_b = 0.037:
    //   R_s = 0.36 x 0.037 + 0.6 x 0.5 + 0.4 x 0.5 = 0.01332 + 0.3 + 0.2 = 0.51332 ohm.
    t = terminal(kTb6612, DriveMode::averaged, averaged(0.6, true, 0.4), 6.1, 0.037);
    EXPECT_NEAR(t.series_resistance_ohm, 0.51332, 1e-15);
    EXPECT_NEAR(t.voltage_V, 0.6 * 6.1, 1e-15);
}

TEST(BridgeDriver, AveragedInputFromTheBridgeFractions) {
    BridgeAverage a;
    a.forward = 0.7;
    a.coast = 0.3;
    BridgeInput in = averaged_input(a);
    EXPECT_TRUE(in.forward);
    EXPECT_EQ(in.duty, 0.7);  // 0.7 - 0: the duty exactly
    EXPECT_EQ(in.brake, 0.0);
    a = BridgeAverage{0.1, 0.5, 0.4, 0.0};
    in = averaged_input(a);
    EXPECT_FALSE(in.forward);
    EXPECT_DOUBLE_EQ(in.duty, 0.4);  // net reverse 0.5 - 0.1
    EXPECT_EQ(in.brake, 0.4);
}

TEST(BridgeDriver, L293dDropsItsDarlingtonSaturationVoltages) {
    // Switched: forward 6.1 - 2.6 = 3.5 V, reverse -3.5 V; coast clamped at
    // 6.1 + 2 x 1.3 = 8.7 V by the built-in diodes; brake a shorted winding.
    MotorTerminal t = terminal(kL293d, DriveMode::switched, switched(BridgeState::forward), 6.1);
    EXPECT_NEAR(t.voltage_V, 3.5, 1e-12);
    EXPECT_EQ(t.supply_factor, 1.0);
    t = terminal(kL293d, DriveMode::switched, switched(BridgeState::reverse), 6.1);
    EXPECT_NEAR(t.voltage_V, -3.5, 1e-12);
    t = terminal(kL293d, DriveMode::switched, switched(BridgeState::coast), 6.1);
    EXPECT_EQ(t.kind, MotorTerminal::Kind::open);
    EXPECT_NEAR(t.clamp_V, 8.7, 1e-12);
    t = terminal(kL293d, DriveMode::switched, switched(BridgeState::brake), 6.1, 0.037);
    EXPECT_EQ(t.voltage_V, 0.0);
    EXPECT_EQ(t.supply_factor, 0.0);
    EXPECT_EQ(t.series_resistance_ohm, 0.0);
    // Averaged, EN at D = 0.5, V_b = 6.1 V behind R_b = 0.037 ohm:
    //   V = D (V_b - drop) = 0.5 x 3.5 = 1.75 V, R_s = D^2 R_b = 0.00925 ohm.
    // A stalled motor 1 (no back-EMF, R_a = 5.32 ohm) then draws
    //   I = 1.75 / (5.32 + 0.00925) = 0.328376 A,
    // the battery D I = 0.164188 A.
    t = terminal(kL293d, DriveMode::averaged, averaged(0.5, true), 6.1, 0.037);
    EXPECT_NEAR(t.voltage_V, 1.75, 1e-12);
    EXPECT_NEAR(t.series_resistance_ohm, 0.00925, 1e-15);
    const double stall_A = t.voltage_V / (5.32 + t.series_resistance_ohm);
    EXPECT_NEAR(stall_A, 0.328376, 1e-6);
    EXPECT_NEAR(t.supply_factor * stall_A, 0.164188, 1e-6);
}

TEST(BridgeDriver, NothingPassesBelowTheDrop) {
    const MotorTerminal t =
        terminal(kL298, DriveMode::switched, switched(BridgeState::forward), 1.0);
    EXPECT_EQ(t.voltage_V, 0.0);  // 1.0 V battery < 1.4 V drop
}

}  // namespace
}  // namespace ddmr::plant
