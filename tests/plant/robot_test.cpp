// Tests for plant/robot: the composed plant. Numbers worked out by hand from
// the defaults (plant/params/default.yaml) unless stated.
#include "plant/robot.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <vector>

#include "plant/motor_driver.hpp"
#include "plant/pwm_waveform.hpp"
#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

/// The thesis shield's bridge input (dir_pwm truth table): the PWM pin's
/// level now (switched), its duty (averaged) and the direction pin.
BridgeInput shield(bool pwm_high, double duty, bool forward) {
    DriverInputLevels pins;
    pins.pwm = pwm_high;
    pins.dir = forward;
    BridgeInput b;
    b.state = bridge_state(DriverType::dir_pwm, pins);
    b.duty = duty;
    b.forward = forward;
    return b;
}

RobotInput averaged(double d1, double d2, bool fwd1 = true, bool fwd2 = true) {
    RobotInput in;
    in.mode = DriveMode::averaged;
    in.bridge[0] = shield(false, d1, fwd1);
    in.bridge[1] = shield(false, d2, fwd2);
    return in;
}

/// Runs `seconds` with a constant input in steps of `h`.
void run(Robot& r, const RobotInput& in, double seconds, double h = 1e-3) {
    EdgeBuffer e;
    r.set_input(in);
    const auto n = static_cast<long>(std::lround(seconds / h));
    for (long k = 0; k < n; ++k) {
        e.clear();
        ASSERT_EQ(r.step(h, e).status, StepStatus::ok);
    }
}

/// Open-loop run with the real 490 Hz waveform (switched) or its duty
/// (averaged, duty = OCR/255); returns the mean wheel speeds [rad/s] over
/// the last `measure_s` seconds. Steps split at every PWM edge, as the HIL does.
struct Mean {
    double wheel1_rad_s;
    double wheel2_rad_s;
    bool current_hit_zero;  // motor 1 current exactly 0 at some step end
};
Mean open_loop(DriveMode mode, double duty, double seconds, double measure_s) {
    Robot r;
    EdgeBuffer e;
    const PhaseCorrectPwm pwm{PhaseCorrectPwm::ocr_for_duty(duty), 0};
    RobotInput in;
    in.mode = mode;
    for (BridgeInput& b : in.bridge) b = shield(false, pwm.duty(), true);
    const std::int64_t end = s_to_cycles(seconds);
    const std::int64_t start_measure = s_to_cycles(seconds - measure_s);
    std::int64_t c = 0;
    double a1 = 0.0, a2 = 0.0;
    bool zero = false;
    while (c < end) {
        std::int64_t next = std::min(end, c + 1600);  // 100 us
        if (mode == DriveMode::switched) next = std::min(next, pwm.next_edge_after(c));
        if (c < start_measure) next = std::min(next, start_measure);
        for (BridgeInput& b : in.bridge) b = shield(pwm.level_at(c), pwm.duty(), true);
        r.set_input(in);
        e.clear();
        EXPECT_EQ(r.step(cycles_to_s(next - c), e).status, StepStatus::ok);
        c = next;
        if (c == start_measure) {
            a1 = r.motor_angle_rad(0);
            a2 = r.motor_angle_rad(1);
        }
        if (r.motor_current_A(0) == 0.0 && c > start_measure) zero = true;
    }
    const double gr = r.params().motor[0].gear_ratio;
    return Mean{(r.motor_angle_rad(0) - a1) / measure_s / gr,
                (r.motor_angle_rad(1) - a2) / measure_s / gr, zero};
}

TEST(Robot, NoLoadWheelSpeedIsTable2s210RpmAtFullDuty) {
    Robot r;
    run(r, averaged(1.0, 1.0), 2.0);
    // default.yaml header: 209.9 RPM (motor 1), 209.4 RPM (motor 2); Table 2: 210 RPM +- 2 %.
    EXPECT_NEAR(rad_s_to_rpm(r.wheel_speed_rad_s(0)), 210.0, 0.02 * 210.0);
    EXPECT_NEAR(rad_s_to_rpm(r.wheel_speed_rad_s(1)), 210.0, 0.02 * 210.0);
    EXPECT_NEAR(rad_s_to_rpm(r.wheel_speed_rad_s(0)), 209.87, 0.01);
    EXPECT_NEAR(rad_s_to_rpm(r.wheel_speed_rad_s(1)), 209.35, 0.01);
}

TEST(Robot, SteadyStateMatchesTheFormulaWithTheBatterySag) {
    Robot r;
    run(r, averaged(0.5, 0.5), 2.0);
    // V = 0.5 (V_b - 1.4), V_b = 6.1 - 0.037 (0.5 I_1 + 0.5 I_2) - 0.72 q/3600 ~ 6.0965;
    // w = (K_t V - R_a T_c) / (R_a F + K_t K_a) with the simulated V_b.
    const double vb = r.battery_voltage_V();
    EXPECT_NEAR(vb, 6.0965, 5e-4);
    const double v = 0.5 * (vb - 1.4);
    EXPECT_NEAR(r.motor_speed_rad_s(0), steady_state_speed_rad_s(r.params().motor[0], v), 1e-3);
}

TEST(Robot, SwitchedAtFullDutyEqualsAveraged) {
    const Mean a = open_loop(DriveMode::averaged, 1.0, 1.0, 0.5);
    const Mean s = open_loop(DriveMode::switched, 1.0, 1.0, 0.5);
    // OCR = 255: the enable pin never drops, the two models are the same
    // equations. Switched mode solves them jointly and exactly, averaged mode
    // motor by motor with the battery coupling held over each step: they
    // agree to 1e-8 relative (measured 5.5e-10).
    EXPECT_NEAR(a.wheel1_rad_s, s.wheel1_rad_s, 1e-8 * a.wheel1_rad_s);
    EXPECT_NEAR(a.wheel2_rad_s, s.wheel2_rad_s, 1e-8 * a.wheel2_rad_s);
}

TEST(Robot, SwitchedAtLowDutyConductsDiscontinuouslyAndDiffersFromAveraged) {
    // Measured (docs/plant.md): at 20 % (OCR 51) the current falls to 0 in every
    // off-time; motor 1's mean wheel speed is 6.8 % BELOW the averaged model's
    // (29.8 RPM): each on-time starts again from zero current.
    const Mean a20 = open_loop(DriveMode::averaged, 0.2, 3.0, 1.0);
    const Mean s20 = open_loop(DriveMode::switched, 0.2, 3.0, 1.0);
    EXPECT_TRUE(s20.current_hit_zero);
    EXPECT_FALSE(a20.current_hit_zero);
    EXPECT_NEAR(rad_s_to_rpm(a20.wheel1_rad_s), 29.8, 0.1);
    EXPECT_NEAR(s20.wheel1_rad_s / a20.wheel1_rad_s - 1.0, -0.068, 0.01);
    // At 50 % (OCR 128) the open bridge lets the motor coast instead of
    // shorting it through the averaged model's 0 V: 57 % FASTER (98 -> 154 RPM).
    const Mean a50 = open_loop(DriveMode::averaged, 0.5, 3.0, 1.0);
    const Mean s50 = open_loop(DriveMode::switched, 0.5, 3.0, 1.0);
    EXPECT_TRUE(s50.current_hit_zero);
    EXPECT_NEAR(s50.wheel1_rad_s / a50.wheel1_rad_s - 1.0, 0.57, 0.02);
}

TEST(Robot, IdenticalMotorsDriveAStraightLine) {
    RobotParams p = default_robot_params();
    p.motor[1] = p.motor[0];
    Robot r(p);
    run(r, averaged(0.7, 0.7), 1.0);
    EXPECT_GT(r.pose().x_m, 0.3);
    // Both motors are solved together (one 4x4 system, coupled_motors.hpp),
    // so their speeds agree to rounding, not bit for bit: 1e-12 m is a
    // millionth of a micrometre.
    EXPECT_NEAR(r.pose().y_m, 0.0, 1e-12);
    EXPECT_NEAR(r.pose().theta_rad, 0.0, 1e-12);
    EXPECT_NEAR(r.body_velocity().omega_rad_s, 0.0, 1e-12);
}

TEST(Robot, UnequalWheelsDriveTheCircleOfRadiusLSumOverDifference) {
    RobotParams p = default_robot_params();
    p.motor[1] = p.motor[0];
    Robot r(p);
    run(r, averaged(0.8, 0.4), 1.0);  // reach steady state
    const double w1 = r.wheel_speed_rad_s(0);
    const double w2 = r.wheel_speed_rad_s(1);
    // Motor 1 (right) faster: counter-clockwise, radius 0.064 (w1 + w2)/(w1 - w2).
    const double radius = 0.064 * (w1 + w2) / (w1 - w2);
    const Pose p0 = r.pose();
    const double cx = p0.x_m - radius * std::sin(p0.theta_rad);
    const double cy = p0.y_m + radius * std::cos(p0.theta_rad);
    run(r, averaged(0.8, 0.4), 2.0);
    EXPECT_GT(r.body_velocity().omega_rad_s, 0.0);
    EXPECT_NEAR(std::hypot(r.pose().x_m - cx, r.pose().y_m - cy), radius, 1e-6);
}

TEST(Robot, OppositeDirectionsRotateInPlace) {
    RobotParams p = default_robot_params();
    p.motor[1] = p.motor[0];
    Robot r(p);
    // Motor 1 forward, motor 2 reverse: v = 0, omega > 0, position unchanged.
    run(r, averaged(0.6, 0.6, true, false), 1.0);
    EXPECT_NEAR(r.pose().x_m, 0.0, 1e-15);
    EXPECT_NEAR(r.pose().y_m, 0.0, 1e-15);
    EXPECT_GT(r.pose().theta_rad, 1.0);
    EXPECT_EQ(r.edge_count(0), r.edge_count(1));  // no direction output: both count up
}

TEST(Robot, ChargeDrawnIsTheIntegralOfTheSupplyCurrent) {
    Robot r;
    run(r, averaged(1.0, 1.0), 1.0);  // steady state
    const double q0 = r.charge_drawn_C();
    // I_1 + I_2 = 0.1203 + 0.1202 A (no-load currents, default.yaml header)
    EXPECT_NEAR(r.supply_current_A(), 0.2405, 1e-3);
    // Trapezoid rule on 1 ms samples of I_1 + I_2 over 2 s (it drifts only as
    // the battery sags, so the rule is exact to ~1e-12 C here).
    double integral = 0.0;
    EdgeBuffer e;
    for (int k = 0; k < 2000; ++k) {
        const double i0 = r.supply_current_A();
        e.clear();
        ASSERT_EQ(r.step(1e-3, e).status, StepStatus::ok);
        integral += 0.5 * (i0 + r.supply_current_A()) * 1e-3;
    }
    EXPECT_NEAR(r.charge_drawn_C() - q0, integral, 1e-9);
    EXPECT_NEAR(integral, 2.0 * 0.2405, 1e-3);  // ~ constant current x 2 s
    // eq. (19): V_b = 6.1 - 0.72 q / 3600 - 0.037 (I_1 + I_2)
    EXPECT_NEAR(r.battery_voltage_V(),
                6.1 - 0.72 * r.charge_drawn_C() / 3600.0 - 0.037 * r.supply_current_A(), 1e-12);
}

TEST(Robot, WithBothBridgesOffTheShaftsCoastAndTheBatteryIsIdle) {
    // Switched mode, full on for 0.5 s, then both enable pins low: the
    // currents fall to zero through the diodes within a few ms; from then on
    // no current flows, so each shaft follows the friction decay on its own,
    // J w' = -F w - T_c:  w(t) = -T_c/F + (w0 + T_c/F) e^{-t F/J},
    // the battery gives nothing (charge constant, V_b = V_0 - k AH), and the
    // encoders still count every boundary the shafts pass.
    Robot r;
    RobotInput in;
    in.mode = DriveMode::switched;
    for (BridgeInput& b : in.bridge) b = shield(true, 1.0, true);
    run(r, in, 0.5);
    for (BridgeInput& b : in.bridge) b = shield(false, 1.0, true);
    EdgeBuffer e;
    r.set_input(in);
    for (int k = 0; k < 1000 && (r.motor_current_A(0) != 0.0 || r.motor_current_A(1) != 0.0); ++k) {
        e.clear();
        ASSERT_EQ(r.step(1e-5, e).status, StepStatus::ok);
    }
    ASSERT_EQ(r.motor_current_A(0), 0.0);
    ASSERT_EQ(r.motor_current_A(1), 0.0);
    const RobotState start = r.state();
    std::uint64_t edges = 0;
    for (int k = 0; k < 1600; ++k) {  // 0.1 s in HIL steps of 62.5 us
        e.clear();
        ASSERT_EQ(r.step(cycles_to_s(1000), e).status, StepStatus::ok);
        edges += e.size();
    }
    EXPECT_EQ(r.charge_drawn_C(), start.battery.charge_drawn_C);
    EXPECT_EQ(r.supply_current_A(), 0.0);
    EXPECT_EQ(r.battery_voltage_V(), 6.1 - 0.72 * start.battery.charge_drawn_C / 3600.0);
    std::uint64_t boundaries = 0;
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        const DcMotorParams& p = r.params().motor[m];
        const double w_ss = p.coulomb_friction_N_m / p.viscous_friction_N_m_s_per_rad;
        const double w0 = start.motor[m].speed_rad_s;
        ASSERT_GT(w0, 500.0);  // still turning fast: no stop inside the 0.1 s
        const double t = r.time_s() - start.t_s;
        const double decay = std::exp(-t * p.viscous_friction_N_m_s_per_rad / p.inertia_kg_m2);
        EXPECT_NEAR(r.motor_speed_rad_s(m), -w_ss + (w0 + w_ss) * decay, 1e-9 * w0);
        EXPECT_EQ(r.motor_current_A(m), 0.0);
        // Boundaries passed: 8 per revolution, phase 0.5 (hall_encoder.hpp).
        const double spacing = 2.0 * kPi / 8.0;
        boundaries += static_cast<std::uint64_t>(std::floor(r.motor_angle_rad(m) / spacing + 0.5) -
                                                 std::floor(start.motor[m].angle_rad / spacing + 0.5));
    }
    EXPECT_EQ(edges, boundaries);
    EXPECT_GT(edges, 100U);
}

TEST(Robot, ARestoredStateContinuesBitForBit) {
    // A turn on the real PWM (OCR 200 / 120), 3000 HIL steps, then a snapshot.
    // 500 more steps from it, and again 500 steps after restoring it, must
    // end at the same bits: everything the steps carry (the heading's cos and
    // sin included) is in RobotState.
    Robot r;
    EdgeBuffer e;
    const std::array<PhaseCorrectPwm, 2> pwm{PhaseCorrectPwm{200, 0}, PhaseCorrectPwm{120, 0}};
    RobotInput in;
    in.mode = DriveMode::switched;
    std::int64_t c = 0;
    auto run_steps = [&](int n) {
        for (int k = 0; k < n; ++k) {
            const std::int64_t next =
                std::min({c + 1000, pwm[0].next_edge_after(c), pwm[1].next_edge_after(c)});
            for (std::size_t m = 0; m < kMotorCount; ++m) in.bridge[m] = shield(pwm[m].level_at(c), 0.0, true);
            r.set_input(in);
            e.clear();
            ASSERT_EQ(r.step(cycles_to_s(next - c), e).status, StepStatus::ok);
            c = next;
        }
    };
    run_steps(3000);
    const RobotState snapshot = r.state();
    const std::int64_t snapshot_cycle = c;
    run_steps(500);
    const Pose first = r.pose();
    r.set_state(snapshot);
    c = snapshot_cycle;
    run_steps(500);
    EXPECT_GT(std::abs(first.theta_rad - snapshot.pose.theta_rad), 1e-3);  // it did turn
    EXPECT_EQ(r.pose().x_m, first.x_m);
    EXPECT_EQ(r.pose().y_m, first.y_m);
    EXPECT_EQ(r.pose().theta_rad, first.theta_rad);
}

TEST(Robot, EncoderEdgesAreSortedAndCountEightPerMotorRevolution) {
    Robot r;
    r.set_input(averaged(0.9, 0.6));
    std::vector<EncoderEdge> all;
    EdgeBuffer e;
    for (int k = 0; k < 1000; ++k) {
        e.clear();
        ASSERT_EQ(r.step(1e-3, e).status, StepStatus::ok);
        for (std::size_t i = 1; i < e.size(); ++i) EXPECT_LE(e[i - 1].t_s, e[i].t_s);
        all.insert(all.end(), e.begin(), e.end());
    }
    for (std::size_t m = 0; m < 2; ++m) {
        // count = floor(8 x motor revolutions + 0.5) (initial phase 0.5)
        const double revs = r.motor_angle_rad(m) / (2 * kPi);
        EXPECT_EQ(r.edge_count(m), static_cast<std::uint64_t>(std::floor(8 * revs + 0.5)));
    }
    EXPECT_EQ(all.size(), r.edge_count(0) + r.edge_count(1));
}

TEST(Robot, BadInputIsReportedAndChangesNothing) {
    Robot r;
    EdgeBuffer e;
    r.set_input(averaged(1.5, 0.0));
    EXPECT_EQ(r.step(1e-3, e).status, StepStatus::bad_input);
    r.set_input(averaged(std::numeric_limits<double>::quiet_NaN(), 0.0));
    EXPECT_EQ(r.step(1e-3, e).status, StepStatus::bad_input);
    r.set_input(averaged(0.5, 0.5));
    EXPECT_EQ(r.step(0.0, e).status, StepStatus::bad_input);
    EXPECT_EQ(r.step(-1e-3, e).status, StepStatus::bad_input);
    EXPECT_EQ(r.step(std::numeric_limits<double>::quiet_NaN(), e).status, StepStatus::bad_input);
    EXPECT_EQ(r.time_s(), 0.0);
    EXPECT_EQ(r.step(1e-3, e).status, StepStatus::ok);
}

TEST(Robot, NonFiniteStateStopsTheRunWithItsTime) {
    Robot r;
    EdgeBuffer e;
    r.set_input(averaged(1.0, 1.0));
    ASSERT_EQ(r.step(0.01, e).status, StepStatus::ok);
    RobotState s = r.state();
    s.motor[1].current_A = std::numeric_limits<double>::quiet_NaN();
    r.set_state(s);
    const StepResult res = r.step(1e-3, e);
    EXPECT_EQ(res.status, StepStatus::diverged);
    EXPECT_NEAR(r.diverged_at_s(), 0.01, 1e-12);
    EXPECT_EQ(r.step(1e-3, e).status, StepStatus::diverged);  // sticky
    EXPECT_STREQ(to_string(res.status), "diverged");
}

TEST(Robot, EdgeBufferOverflowIsReported) {
    Robot r;
    EdgeBuffer e;
    r.set_input(averaged(1.0, 1.0));
    // 1 s at full speed: ~2 x 1300 edges > 256.
    const StepResult res = r.step(1.0, e);
    EXPECT_EQ(res.status, StepStatus::edge_overflow);
    EXPECT_EQ(e.size(), EdgeBuffer::kCapacity);
    EXPECT_EQ(e.dropped() + e.size(), r.edge_count(0) + r.edge_count(1));
}

// ---- other motor drivers, braking, quadrature encoders ----------------------

/// The defaults with an ideal pack (R_b = 0, no sag: the source stays 6.1 V)
/// and both motors on `chip`.
RobotParams ideal_battery(DriverChip chip) {
    RobotParams p = default_robot_params();
    p.battery.internal_resistance_ohm = 0.0;
    p.battery.sag_V_per_Ah = 0.0;
    p.chip = {chip, chip};
    return p;
}

RobotInput switched_states(BridgeState s1, BridgeState s2) {
    RobotInput in;
    in.mode = DriveMode::switched;
    in.bridge[0].state = s1;
    in.bridge[1].state = s2;
    return in;
}

TEST(Robot, SteadyWheelSpeedThroughEachChipsDropAndOnResistance) {
    // Motor 1 (R_a 5.32, K_t = K_a = 0.00384, F 2.2e-7, T_c 2.3e-4), driven
    // forward all the time, battery 6.1 V with R_b = 0:
    //   w = (K_t V - (R_a + R_on) T_c) / ((R_a + R_on) F + K_t K_a),  V = 6.1 - drop
    //   L298    V 4.7, R 5.32: (0.018048 - 0.0012236) / (1.1704e-6 + 1.47456e-5) = 1057.07 rad/s
    //   TB6612  V 6.1, R 5.82: (0.023424 - 0.0013386) / (1.2804e-6 + 1.47456e-5) = 1378.10 rad/s
    //   DRV8833 V 6.1, R 5.68: (0.023424 - 0.0013064) / (1.2496e-6 + 1.47456e-5) = 1382.76 rad/s
    //   L293D   V 3.5, R 5.32: (0.01344 - 0.0012236) / (1.1704e-6 + 1.47456e-5) = 767.55 rad/s
    // (210.3, 274.2, 275.1, 152.7 RPM at the wheel). 2 s is 29 mechanical time constants.
    struct Case {
        DriverChip chip;
        double hand_rad_s;
    };
    for (const Case& c : {Case{DriverChip::l298, 1057.07}, Case{DriverChip::tb6612, 1378.10},
                          Case{DriverChip::drv8833, 1382.76}, Case{DriverChip::l293d, 767.55}}) {
        const RobotParams p = ideal_battery(c.chip);
        Robot r(p);
        run(r, switched_states(BridgeState::forward, BridgeState::forward), 2.0);
        const BridgeParams& b = bridge_params(p, 0);
        const DcMotorParams& m = p.motor[0];
        const double v = 6.1 - b.drop_V;
        const double rs = m.resistance_ohm + b.on_resistance_ohm;
        const double w = (m.torque_N_m_per_A * v - rs * m.coulomb_friction_N_m) /
                         (rs * m.viscous_friction_N_m_s_per_rad +
                          m.torque_N_m_per_A * m.back_emf_V_s_per_rad);
        EXPECT_NEAR(w, c.hand_rad_s, 0.01) << static_cast<int>(c.chip);
        EXPECT_NEAR(r.motor_speed_rad_s(0), w, 1e-9 * w) << static_cast<int>(c.chip);
        // The same through the averaged model at full duty.
        Robot a(p);
        run(a, averaged(1.0, 1.0), 2.0);
        EXPECT_NEAR(a.motor_speed_rad_s(0), w, 1e-9 * w) << static_cast<int>(c.chip);
    }
}

TEST(Robot, L293dAtDutyPointSixThroughItsTruthTable) {
    // Motor 1 on an L293D, EN at duty 0.6, IN1 H, IN2 L, averaged, 6.1 V with
    // R_b = 0: average_bridge gives forward 0.6, coast 0.4; the terminal sees
    //   V = 0.6 (6.1 - 2.6) = 2.1 V, no series resistance, and settles at
    //   w = (K_t V - R_a T_c) / (R_a F + K_t K_a)
    //     = (0.00384 x 2.1 - 5.32 x 2.3e-4) / (5.32 x 2.2e-7 + 0.00384^2)
    //     = 0.0068404 / 1.5916e-5 = 429.78 rad/s (85.5 RPM at the wheel),
    //   drawing I = (V - K_a w) / R_a = (2.1 - 1.65036) / 5.32 = 0.08452 A.
    const RobotParams p = ideal_battery(DriverChip::l293d);
    DriverInputDuties d;
    d.en = 0.6;
    d.in1 = 1.0;
    RobotInput in;
    in.mode = DriveMode::averaged;
    in.bridge[0] = averaged_input(average_bridge(DriverType::l293d, d));
    in.bridge[1] = in.bridge[0];
    EXPECT_EQ(in.bridge[0].duty, 0.6);
    Robot r(p);
    run(r, in, 2.0);
    EXPECT_NEAR(r.motor_speed_rad_s(0), 429.78, 0.01);
    EXPECT_NEAR(r.motor_current_A(0), 0.08452, 1e-5);
}

TEST(Robot, BrakeStopsFasterThanCoastByTheElectricalDamping) {
    // Both motors = motor 1, at w0 = 1000 rad/s with I = 0; TB6612. Motor 1
    // brakes (winding shorted through 0.5 ohm), motor 2 coasts (open, I stays 0).
    // Coast, J w' = -F w - T_c:
    //   w(t) = (w0 + T_c/F) e^{-t F/J} - T_c/F, J/F = 0.8636 s, T_c/F = 1045.45 rad/s
    //   half speed at t = (J/F) ln((1000 + 1045.45) / (500 + 1045.45)) = 0.24208 s.
    // Brake, neglecting L_a (the current follows w within L_a/(R_a + R_brake) = 0.40 ms):
    //   F_e = K_t K_a / (R_a + R_brake) = 1.47456e-5 / 5.82 = 2.5336e-6 N m s/rad,
    //   F' = F + F_e = 2.7536e-6, J/F' = 69.00 ms, T_c/F' = 83.53 rad/s,
    //   half speed at t = 0.069 ln(1083.53 / 583.53) = 0.042703 s: 5.67 x sooner.
    // The simulation includes L_a: the braking current builds up over ~L_a/R
    // (0.40 ms), so its half-speed time comes later (measured 0.042816 s,
    // +0.11 ms); tolerance 1 ms.
    RobotParams p = ideal_battery(DriverChip::tb6612);
    p.motor[1] = p.motor[0];
    Robot r(p);
    RobotState s = r.state();
    for (DcMotorState& m : s.motor) m.speed_rad_s = 1000.0;
    r.set_state(s);
    r.set_input(switched_states(BridgeState::brake, BridgeState::coast));
    EdgeBuffer e;
    std::array<double, 2> half_s{-1.0, -1.0};
    const double h = 1e-5;
    for (int k = 1; k <= 30000 && half_s[1] < 0.0; ++k) {
        std::array<double, 2> before{r.motor_speed_rad_s(0), r.motor_speed_rad_s(1)};
        e.clear();
        ASSERT_EQ(r.step(h, e).status, StepStatus::ok);
        for (std::size_t m = 0; m < 2; ++m) {
            const double w = r.motor_speed_rad_s(m);
            if (half_s[m] < 0.0 && w <= 500.0) {  // linear interpolation inside the step
                half_s[m] = (k - 1) * h + h * (before[m] - 500.0) / (before[m] - w);
            }
        }
        EXPECT_EQ(r.supply_current_A(), 0.0);  // the battery sees nothing
    }
    EXPECT_EQ(r.charge_drawn_C(), 0.0);
    EXPECT_NEAR(half_s[1], 0.24208, 1e-5);  // coast: exact closed form
    EXPECT_NEAR(half_s[0], 0.042703, 1e-3);
    EXPECT_GT(half_s[0], 0.042703);         // L_a only delays the braking current
    EXPECT_NEAR(half_s[1] / half_s[0], 5.67, 0.15);
    std::printf("half speed: brake %.6f s, coast %.6f s\n", half_s[0], half_s[1]);
}

TEST(Robot, ABrakingMotorLeavesTheBatteryToTheOther) {
    // L298s, R_b = 0.037 ohm, no sag. Motor 1 drives forward, motor 2 brakes
    // (supply factor 0): motor 1 alone loads the pack, so it settles at the
    // single-motor speed with R_a + R_b (0.037 R_b x its own current only):
    //   w = (0.00384 x 4.7 - 5.357 x 2.3e-4) / (5.357 x 2.2e-7 + 1.47456e-5) = 1056.00 rad/s.
    RobotParams p = default_robot_params();
    p.battery.sag_V_per_Ah = 0.0;
    Robot r(p);
    RobotState s = r.state();
    s.motor[1].speed_rad_s = 800.0;
    r.set_state(s);
    run(r, switched_states(BridgeState::forward, BridgeState::brake), 2.0);
    EXPECT_NEAR(r.motor_speed_rad_s(0), 1056.00, 0.01);
    EXPECT_EQ(r.motor_speed_rad_s(1), 0.0);  // braked to a stop, held by stiction
    EXPECT_NEAR(r.supply_current_A(), r.motor_current_A(0), 1e-15);
}

TEST(Robot, QuadratureEncodersCountBothOutputsAndReportTheirLevels) {
    RobotParams p = default_robot_params();
    for (HallEncoderParams& e : p.encoder) e.channels = 2;
    Robot r(p);
    // At angle 0: j = floor(0 + 2 x 0.5) = 1, (A, B) = (1, 0).
    EXPECT_TRUE(r.encoder_level(0, 0));
    EXPECT_FALSE(r.encoder_level(0, 1));
    r.set_input(averaged(0.9, 0.6));
    std::array<bool, 2> a{true, true};
    std::array<bool, 2> b{false, false};
    EdgeBuffer e;
    for (int k = 0; k < 500; ++k) {
        e.clear();
        ASSERT_EQ(r.step(1e-3, e).status, StepStatus::ok);
        for (const EncoderEdge& edge : e) (edge.signal == 0 ? a : b)[edge.channel] = edge.level;
    }
    for (std::size_t m = 0; m < 2; ++m) {
        // 2 x 8 sub-boundaries per motor revolution, from j = 1.
        const double revs = r.motor_angle_rad(m) / (2 * kPi);
        EXPECT_EQ(r.edge_count(m), static_cast<std::uint64_t>(std::floor(16 * revs + 1) - 1));
        EXPECT_EQ(r.encoder_level(m, 0), a[m]);
        EXPECT_EQ(r.encoder_level(m, 1), b[m]);
    }
}

// ---- halving the step in a closed loop ------------------------------------

/// A firmware-like loop (the thesis's Kanayama tracker of the 0.6 m, 12 s
/// circle): every 10 ms it reads the edge counts, dead-reckons, and sets the
/// duties (|Vdc| / 255) and directions. Returns the plant's final pose.
Pose closed_loop(const StepperConfig& step, DriveMode mode) {
    RobotParams p = default_robot_params();
    p.stepper = step;
    const double max_step_s = step.max_step_s;
    Robot r(p);
    EdgeBuffer e;
    const double dt = 0.01, r1 = 0.03215, big_r = 7.874, ka = 0.0054, gr = 48, batt = 0.164;
    const double radpuls = 2 * kPi / 384, kx = 1, ky = 6, kw = 8, vref = 0.2, wref = 0.2;
    double ex = 0, ey = 0, th = 0, t = 0, angref = 1.571;
    std::uint64_t old1 = 0, old2 = 0;
    std::array<PhaseCorrectPwm, 2> pwm{PhaseCorrectPwm{50, 0}, PhaseCorrectPwm{30, 1000}};
    std::array<bool, 2> fwd{true, true};
    std::int64_t c = 0;
    for (int loop = 0; loop < 1200; ++loop) {
        // Plant runs one 10 ms loop with the current outputs.
        const std::int64_t loop_end = c + s_to_cycles(dt);
        while (c < loop_end) {
            std::int64_t next = std::min(loop_end, c + s_to_cycles(max_step_s));
            RobotInput in;
            in.mode = mode;
            for (std::size_t m = 0; m < 2; ++m) {
                if (mode == DriveMode::switched) next = std::min(next, pwm[m].next_edge_after(c));
                in.bridge[m] = shield(pwm[m].level_at(c), pwm[m].duty(), fwd[m]);
            }
            r.set_input(in);
            e.clear();
            EXPECT_EQ(r.step(cycles_to_s(next - c), e).status, StepStatus::ok);
            c = next;
        }
        // Controller.
        const double p1 = static_cast<double>(r.edge_count(0) - old1) * radpuls / dt;
        const double p2 = static_cast<double>(r.edge_count(1) - old2) * radpuls / dt;
        old1 = r.edge_count(0);
        old2 = r.edge_count(1);
        const double vel = 0.5 * r1 * (p1 + p2), om = big_r * r1 * (p1 - p2);
        th += dt * om;
        ex += dt * std::cos(th) * vel;
        ey += dt * std::sin(th) * vel;
        const double errx = 0.6 * std::cos(0.5236 * t) - ex, erry = 0.6 * std::sin(0.5236 * t) - ey;
        const double et = angref - th;
        const double exr = std::cos(th) * errx + std::sin(th) * erry;
        const double eyr = -std::sin(th) * errx + std::cos(th) * erry;
        const double v = vref * std::cos(et) + kx * exr;
        const double w = wref + vref * (ky * eyr + kw * std::sin(et));
        const std::array<double, 2> vdc{255 * gr * ka * (30.3 * v + 1.92 * w) * batt,
                                        255 * gr * ka * (30.3 * v - 1.92 * w) * batt};
        for (std::size_t m = 0; m < 2; ++m) {
            fwd[m] = vdc[m] >= 0;
            pwm[m].ocr = static_cast<std::uint8_t>(std::min(255.0, std::floor(std::abs(vdc[m]))));
        }
        t += dt;
        angref += dt * 0.5236;
    }
    return r.pose();
}

TEST(Robot, HalvingTheStepMovesA12sClosedLoopRunByLessThanATenthMm) {
    for (DriveMode mode : {DriveMode::averaged, DriveMode::switched}) {
        const StepperConfig step = default_robot_params().stepper;  // 1e-4 s, 2e-5 s
        const Pose a = closed_loop(step, mode);
        const Pose b = closed_loop({step.max_step_s / 2, step.event_step_s / 2}, mode);
        const double d = std::hypot(a.x_m - b.x_m, a.y_m - b.y_m);
        EXPECT_LT(d, 1e-4) << "mode " << static_cast<int>(mode);
        // It did go somewhere: a 0.6 m circle, not a robot standing still.
        EXPECT_GT(std::hypot(a.x_m, a.y_m), 0.2);
        RecordProperty(mode == DriveMode::averaged ? "averaged_m" : "switched_m", std::to_string(d));
        std::printf("mode %d: end (%.4f, %.4f), halving moved it %.3g m\n", static_cast<int>(mode),
                    a.x_m, a.y_m, d);
    }
}

}  // namespace
}  // namespace ddmr::plant
