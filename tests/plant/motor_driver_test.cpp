// Tests for plant/motor_driver: every row of each datasheet truth table
// (/work/shared/DRIVERS.md), and the averaged bridge over input duties.
#include "plant/motor_driver.hpp"

#include <gtest/gtest.h>

namespace ddmr::plant {
namespace {

constexpr bool H = true;
constexpr bool L = false;
constexpr BridgeState kCoast = BridgeState::coast;
constexpr BridgeState kForward = BridgeState::forward;
constexpr BridgeState kReverse = BridgeState::reverse;
constexpr BridgeState kBrake = BridgeState::brake;

BridgeState dir_pwm(bool pwm, bool dir) {
    DriverInputLevels in;
    in.pwm = pwm;
    in.dir = dir;
    return bridge_state(DriverType::dir_pwm, in);
}
BridgeState l298n(bool en, bool in1, bool in2) {
    DriverInputLevels in;
    in.en = en;
    in.in1 = in1;
    in.in2 = in2;
    return bridge_state(DriverType::l298n, in);
}
BridgeState l293d(bool en, bool in1, bool in2) {
    DriverInputLevels in;
    in.en = en;
    in.in1 = in1;
    in.in2 = in2;
    return bridge_state(DriverType::l293d, in);
}
BridgeState tb6612(bool in1, bool in2, bool pwm, bool stby) {
    DriverInputLevels in;
    in.in1 = in1;
    in.in2 = in2;
    in.pwm = pwm;
    in.stby = stby;
    return bridge_state(DriverType::tb6612, in);
}
BridgeState drv8833(bool in1, bool in2, bool sleep) {
    DriverInputLevels in;
    in.in1 = in1;
    in.in2 = in2;
    in.sleep = sleep;
    return bridge_state(DriverType::drv8833, in);
}

BridgeState l9110(bool ia, bool ib) {
    DriverInputLevels in;
    in.in1 = ia;
    in.in2 = ib;
    return bridge_state(DriverType::l9110, in);
}

TEST(MotorDriver, ChipOfEachType) {
    EXPECT_EQ(chip_of(DriverType::dir_pwm), DriverChip::l298);
    EXPECT_EQ(chip_of(DriverType::l298n), DriverChip::l298);
    EXPECT_EQ(chip_of(DriverType::tb6612), DriverChip::tb6612);
    EXPECT_EQ(chip_of(DriverType::drv8833), DriverChip::drv8833);
    EXPECT_EQ(chip_of(DriverType::l293d), DriverChip::l293d);
    EXPECT_EQ(chip_of(DriverType::l9110), DriverChip::l9110);
}

TEST(MotorDriver, DirPwmIsTheThesisShield) {
    // PWM (the L298's EN) low: free running; high: DIR gives the direction.
    EXPECT_EQ(dir_pwm(L, L), kCoast);
    EXPECT_EQ(dir_pwm(L, H), kCoast);
    EXPECT_EQ(dir_pwm(H, H), kForward);
    EXPECT_EQ(dir_pwm(H, L), kReverse);
}

TEST(MotorDriver, L298nFollowsFigure6) {
    // ST L298, Figure 6: EN H, C H, D L forward; C L, D H reverse; C = D fast
    // motor stop (H H and L L); EN L free running motor stop, any C, D.
    EXPECT_EQ(l298n(H, H, L), kForward);
    EXPECT_EQ(l298n(H, L, H), kReverse);
    EXPECT_EQ(l298n(H, H, H), kBrake);
    EXPECT_EQ(l298n(H, L, L), kBrake);
    for (bool c : {L, H}) {
        for (bool d : {L, H}) EXPECT_EQ(l298n(L, c, d), kCoast) << c << d;
    }
}

TEST(MotorDriver, L293dFollowsFigure5) {
    // TI L293D, Figure 5 (EN, 1A, 2A): H H L "turn left" = forward (IN1 H, as
    // the L298's), H L H "turn right" = reverse, 1A = 2A fast motor stop;
    // EN L: outputs Z (function table), so coast whatever 1A and 2A are.
    EXPECT_EQ(l293d(H, H, L), kForward);
    EXPECT_EQ(l293d(H, L, H), kReverse);
    EXPECT_EQ(l293d(H, L, L), kBrake);
    EXPECT_EQ(l293d(H, H, H), kBrake);
    for (bool a1 : {L, H}) {
        for (bool a2 : {L, H}) EXPECT_EQ(l293d(L, a1, a2), kCoast) << a1 << a2;
    }
    // The same table as the l298n type, row for row.
    for (bool en : {L, H}) {
        for (bool a1 : {L, H}) {
            for (bool a2 : {L, H}) EXPECT_EQ(l293d(en, a1, a2), l298n(en, a1, a2)) << en << a1 << a2;
        }
    }
}

TEST(MotorDriver, Tb6612FollowsTheHSwControlFunctionTable) {
    // Toshiba p. 4, row by row (IN1, IN2, PWM, STBY):
    EXPECT_EQ(tb6612(H, H, H, H), kBrake);    // short brake
    EXPECT_EQ(tb6612(H, H, L, H), kBrake);    // short brake (PWM H/L)
    EXPECT_EQ(tb6612(L, H, H, H), kReverse);  // CCW: OUT1 L, OUT2 H
    EXPECT_EQ(tb6612(L, H, L, H), kBrake);    // short brake
    EXPECT_EQ(tb6612(H, L, H, H), kForward);  // CW: OUT1 H, OUT2 L
    EXPECT_EQ(tb6612(H, L, L, H), kBrake);    // short brake
    EXPECT_EQ(tb6612(L, L, H, H), kCoast);    // stop: high-Z
    EXPECT_EQ(tb6612(L, L, L, H), kCoast);    // not in the table: taken as stop
    for (bool in1 : {L, H}) {                 // standby: high-Z whatever the rest
        for (bool in2 : {L, H}) {
            for (bool pwm : {L, H}) EXPECT_EQ(tb6612(in1, in2, pwm, L), kCoast);
        }
    }
}

TEST(MotorDriver, Drv8833FollowsTable1) {
    // TI §7.3.2 Table 1 (xIN1, xIN2): 00 coast, 01 reverse, 10 forward, 11 brake.
    EXPECT_EQ(drv8833(L, L, H), kCoast);
    EXPECT_EQ(drv8833(L, H, H), kReverse);
    EXPECT_EQ(drv8833(H, L, H), kForward);
    EXPECT_EQ(drv8833(H, H, H), kBrake);
    for (bool in1 : {L, H}) {  // nSLEEP low: bridges Hi-Z, inputs ignored
        for (bool in2 : {L, H}) EXPECT_EQ(drv8833(in1, in2, L), kCoast);
    }
}

TEST(MotorDriver, L9110FollowsTheModulesTable) {
    // Vendors' table (IA, IB) -> (OA, OB): HL forward (H, L), LH reverse
    // (L, H), LL (L, L) and HH (H, H): both outputs on one rail, a shorted
    // winding: brake. Never a coast: no input turns the outputs off.
    EXPECT_EQ(l9110(H, L), kForward);
    EXPECT_EQ(l9110(L, H), kReverse);
    EXPECT_EQ(l9110(L, L), kBrake);
    EXPECT_EQ(l9110(H, H), kBrake);
    // PWM on IA (duty 0.6) with IB low: forward 60 % of the period, the
    // off-time braking (slow decay), not coasting.
    DriverInputDuties d;
    d.in1 = 0.6;
    const BridgeAverage a = average_bridge(DriverType::l9110, d);
    EXPECT_DOUBLE_EQ(a.forward, 0.6);
    EXPECT_DOUBLE_EQ(a.brake, 0.4);
    EXPECT_DOUBLE_EQ(a.coast, 0.0);
}

TEST(MotorDriver, InputsATypeDoesNotHaveAreIgnored) {
    DriverInputLevels in;
    in.pwm = H;
    in.dir = H;
    const BridgeState s = bridge_state(DriverType::dir_pwm, in);
    in.en = H;  // not a dir_pwm input
    in.in2 = H;
    in.sleep = H;
    EXPECT_EQ(bridge_state(DriverType::dir_pwm, in), s);
    DriverInputLevels d;
    d.in1 = H;
    d.sleep = H;
    d.pwm = L;  // the DRV8833 has no PWM input: still forward
    d.stby = L;
    EXPECT_EQ(bridge_state(DriverType::drv8833, d), kForward);
}

TEST(MotorDriver, AveragedDirPwmIsTheDutyExactly) {
    // One switching input (PWM at 0.3, DIR high): 0.3 forward, 0.7 coast,
    // bit for bit (the thesis's averaged model takes the duty as it is).
    DriverInputDuties d;
    d.pwm = 0.3;
    d.dir = 1.0;
    const BridgeAverage a = average_bridge(DriverType::dir_pwm, d);
    EXPECT_EQ(a.forward, 0.3);
    EXPECT_EQ(a.coast, 1.0 - 0.3);
    EXPECT_EQ(a.reverse, 0.0);
    EXPECT_EQ(a.brake, 0.0);
    d.dir = 0.0;
    EXPECT_EQ(average_bridge(DriverType::dir_pwm, d).reverse, 0.3);
}

TEST(MotorDriver, AveragedOneSwitchingInputIsExact) {
    // TB6612, IN1 H, IN2 L, STBY H, PWM at 0.6: drive 0.6, short brake 0.4
    // (slow decay, the datasheet's PWM mode).
    DriverInputDuties t;
    t.in1 = 1.0;
    t.stby = 1.0;
    t.pwm = 0.6;
    BridgeAverage a = average_bridge(DriverType::tb6612, t);
    EXPECT_EQ(a.forward, 0.6);
    EXPECT_DOUBLE_EQ(a.brake, 0.4);
    EXPECT_EQ(a.coast, 0.0);
    // DRV8833 Table 2: xIN1 = 1, xIN2 = PWM at 0.25 is forward, slow decay:
    // it drives while the PWM input is LOW (0.75) and brakes while high (0.25).
    DriverInputDuties v;
    v.in1 = 1.0;
    v.in2 = 0.25;
    v.sleep = 1.0;
    a = average_bridge(DriverType::drv8833, v);
    EXPECT_DOUBLE_EQ(a.forward, 0.75);
    EXPECT_DOUBLE_EQ(a.brake, 0.25);
    // xIN1 = PWM at 0.25, xIN2 = 0: forward fast decay, coast in the off-time.
    v.in1 = 0.25;
    v.in2 = 0.0;
    a = average_bridge(DriverType::drv8833, v);
    EXPECT_DOUBLE_EQ(a.forward, 0.25);
    EXPECT_DOUBLE_EQ(a.coast, 0.75);
}

TEST(MotorDriver, AveragedL293dWithPwmOnTheEnable) {
    // L293D, EN at 0.6, 1A H, 2A L: forward while EN is high (0.6), outputs Z
    // (coast) while low (0.4). With 1A = 2A = L instead: brake 0.6 (fast motor
    // stop), coast 0.4.
    DriverInputDuties d;
    d.en = 0.6;
    d.in1 = 1.0;
    BridgeAverage a = average_bridge(DriverType::l293d, d);
    EXPECT_EQ(a.forward, 0.6);
    EXPECT_DOUBLE_EQ(a.coast, 0.4);
    EXPECT_EQ(a.reverse, 0.0);
    EXPECT_EQ(a.brake, 0.0);
    d.in1 = 0.0;
    a = average_bridge(DriverType::l293d, d);
    EXPECT_EQ(a.brake, 0.6);
    EXPECT_DOUBLE_EQ(a.coast, 0.4);
    d.in2 = 1.0;
    EXPECT_EQ(average_bridge(DriverType::l293d, d).reverse, 0.6);
}

TEST(MotorDriver, AveragedTwoSwitchingInputsAreTakenIndependent) {
    // L298N with EN at 0.5 and IN1 at 0.4, IN2 low. Independent levels:
    //   EN H (0.5) x IN1 H (0.4) = 0.20 forward
    //   EN H (0.5) x IN1 L (0.6) = 0.30 brake (IN1 = IN2 = L: fast motor stop)
    //   EN L (0.5)               = 0.50 coast
    DriverInputDuties d;
    d.en = 0.5;
    d.in1 = 0.4;
    const BridgeAverage a = average_bridge(DriverType::l298n, d);
    EXPECT_DOUBLE_EQ(a.forward, 0.20);
    EXPECT_DOUBLE_EQ(a.brake, 0.30);
    EXPECT_DOUBLE_EQ(a.coast, 0.50);
    EXPECT_EQ(a.reverse, 0.0);
    EXPECT_DOUBLE_EQ(a.forward + a.reverse + a.brake + a.coast, 1.0);
}

TEST(MotorDriver, AveragedStaticInputsGiveOneStateAndOutOfRangeDutiesClamp) {
    DriverInputDuties d;
    d.in1 = 1.0;
    d.in2 = 1.0;
    d.sleep = 1.0;
    EXPECT_EQ(average_bridge(DriverType::drv8833, d).brake, 1.0);
    d.in2 = -0.5;  // below 0: low
    d.in1 = 7.0;   // above 1: high
    EXPECT_EQ(average_bridge(DriverType::drv8833, d).forward, 1.0);
    d.sleep = 0.0;
    EXPECT_EQ(average_bridge(DriverType::drv8833, d).coast, 1.0);
}

}  // namespace
}  // namespace ddmr::plant
