// Tests for plant/coupled_motors: both motors solved together, coupled
// through the battery's internal resistance R_b. Reference: classic RK4 on
// DcMotor's derivative() with the battery voltage recomputed from both
// currents at every stage (an independent path through the model).
#include "plant/coupled_motors.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "plant/motor_stepper.hpp"

namespace ddmr::plant {
namespace {

constexpr double kRb = 0.037;      // R_b [ohm], default.yaml
constexpr double kSource = 6.1;    // V_s [V]
constexpr double kDrop = 1.4;      // bridge drop [V]
constexpr double kClamp = 7.7;     // V_s + 2 V_f [V]

using Pair = std::array<DcMotorState, 2>;

/// One bridge as the reference sees it: enabled with direction sign, or off.
struct Bridge {
    bool on = true;
    double sign = 1.0;
};

/// The coupled terminal the Robot would build for `b` at current `i`.
CoupledTerminal terminal_of(const Bridge& b, double i) {
    MotorTerminal u;
    if (b.on) {
        u.kind = MotorTerminal::Kind::driven;
        u.supply_factor = b.sign;
        u.voltage_V = b.sign * (kSource - kDrop);
    } else {
        u.kind = MotorTerminal::Kind::open;
        u.clamp_V = kClamp;
    }
    return coupled_terminal(u, i);
}

/// d/dt of both motors with V_b = V_s - R_b (s1 I1 + s2 I2).
std::array<DcMotorDerivative, 2> coupled_derivative(const std::array<DcMotorParams, 2>& p,
                                                    const Pair& x,
                                                    const std::array<Bridge, 2>& b, double rb) {
    std::array<double, 2> s{};
    for (std::size_t m = 0; m < 2; ++m) {
        const double i = x[m].current_A;
        s[m] = b[m].on ? b[m].sign : -(i > 0.0 ? 1.0 : (i < 0.0 ? -1.0 : 0.0));
    }
    const double vb = kSource - rb * (s[0] * x[0].current_A + s[1] * x[1].current_A);
    std::array<DcMotorDerivative, 2> d{};
    for (std::size_t m = 0; m < 2; ++m) {
        MotorTerminal u;
        if (b[m].on) {
            u.kind = MotorTerminal::Kind::driven;
            u.voltage_V = b[m].sign * (vb - kDrop);
        } else {
            u.kind = MotorTerminal::Kind::open;
            u.clamp_V = vb + (kClamp - kSource);
        }
        d[m] = derivative(p[m], x[m], u);
    }
    return d;
}

struct Rk4Result {
    Pair x{};
    double supply_charge_C = 0.0;
};

Rk4Result rk4(const std::array<DcMotorParams, 2>& p, Pair x, const std::array<Bridge, 2>& b,
              double rb, double t, int n) {
    const double h = t / n;
    auto add = [](Pair s, const std::array<DcMotorDerivative, 2>& d, double k) {
        for (std::size_t m = 0; m < 2; ++m) {
            s[m].current_A += k * d[m].current_A_s;
            s[m].speed_rad_s += k * d[m].speed_rad_s2;
            s[m].angle_rad += k * d[m].angle_rad_s;
        }
        return s;
    };
    auto supply = [&](const Pair& s) {
        double sum = 0.0;
        for (std::size_t m = 0; m < 2; ++m) {
            const double i = s[m].current_A;
            sum += b[m].on ? b[m].sign * i : -std::abs(i);
        }
        return sum;
    };
    Rk4Result r;
    for (int k = 0; k < n; ++k) {
        const auto k1 = coupled_derivative(p, x, b, rb);
        const Pair x2 = add(x, k1, h / 2);
        const auto k2 = coupled_derivative(p, x2, b, rb);
        const Pair x3 = add(x, k2, h / 2);
        const auto k3 = coupled_derivative(p, x3, b, rb);
        const Pair x4 = add(x, k3, h);
        const auto k4 = coupled_derivative(p, x4, b, rb);
        r.supply_charge_C += h / 6 * (supply(x) + 2 * supply(x2) + 2 * supply(x3) + supply(x4));
        for (std::size_t m = 0; m < 2; ++m) {
            x[m].current_A += h / 6 * (k1[m].current_A_s + 2 * k2[m].current_A_s + 2 * k3[m].current_A_s + k4[m].current_A_s);
            x[m].speed_rad_s += h / 6 * (k1[m].speed_rad_s2 + 2 * k2[m].speed_rad_s2 + 2 * k3[m].speed_rad_s2 + k4[m].speed_rad_s2);
            x[m].angle_rad += h / 6 * (k1[m].angle_rad_s + 2 * k2[m].angle_rad_s + 2 * k3[m].angle_rad_s + k4[m].angle_rad_s);
        }
    }
    r.x = x;
    return r;
}

std::array<DcMotorParams, 2> motors() {
    std::array<DcMotorParams, 2> p{};
    p[1].resistance_ohm = 5.41;  // motor 2 of Table 2
    p[1].inductance_H = 2.4e-3;
    return p;
}

std::array<CoupledTerminal, 2> terminals(const std::array<Bridge, 2>& b, const Pair& x) {
    return {terminal_of(b[0], x[0].current_A), terminal_of(b[1], x[1].current_A)};
}

TEST(CoupledMotors, SystemMatrixCouplesTheCurrentsThroughTheBattery) {
    // Row I_1: -(R_a1 + s1^2 R_b)/L_1 on I_1 and -s1 s2 R_b / L_1 on I_2.
    const auto p = motors();
    const CoupledMotorStepper s(p[0], p[1]);
    const Eigen::Matrix4d a = s.system_matrix(1.0, -0.5, kRb);
    EXPECT_DOUBLE_EQ(a(0, 0), -(5.32 + kRb) / 2.3e-3);
    EXPECT_DOUBLE_EQ(a(0, 2), 0.5 * kRb / 2.3e-3);
    EXPECT_DOUBLE_EQ(a(2, 0), 0.5 * kRb / 2.4e-3);
    EXPECT_DOUBLE_EQ(a(2, 2), -(5.41 + 0.25 * kRb) / 2.4e-3);
    EXPECT_DOUBLE_EQ(a(1, 0), 0.00384 / 1.9e-7);  // K_t / J
    EXPECT_EQ(a(1, 2), 0.0);                      // no mechanical coupling
}

TEST(CoupledMotors, BridgeResistanceAddsToItsMotorsDiagonalOnly) {
    // Row I_1: -(R_a1 + R_s1 + s1^2 R_b)/L_1; the coupling entries are unchanged.
    const auto p = motors();
    const CoupledMotorStepper s(p[0], p[1]);
    const Eigen::Matrix4d a = s.system_matrix(1.0, 0.0, kRb, 0.5, 0.32);
    const Eigen::Matrix4d a0 = s.system_matrix(1.0, 0.0, kRb);
    EXPECT_DOUBLE_EQ(a(0, 0), -(5.32 + 0.5 + kRb) / 2.3e-3);
    EXPECT_DOUBLE_EQ(a(2, 2), -(5.41 + 0.32) / 2.4e-3);
    EXPECT_EQ(a(0, 2), a0(0, 2));
    EXPECT_EQ(a(0, 1), a0(0, 1));
    // Zero bridge resistance: A bit for bit as without it (R_a + 0 == R_a).
    EXPECT_EQ(s.system_matrix(1.0, -0.5, kRb, 0.0, 0.0), s.system_matrix(1.0, -0.5, kRb));
}

TEST(CoupledMotors, SteadyStateWithOnResistanceMatchesTheHandFormula) {
    // Identical motors on a MOSFET bridge (no drop, R_on = 0.5 ohm), both
    // forward: E = V_s, each motor behind R_a + R_on + 2 R_b:
    //   w = (K_t E - R T_c) / (R F + K_t K_a), R = 5.32 + 0.5 + 0.074 = 5.894 ohm.
    const DcMotorParams m;
    CoupledMotorStepper joint(m, m);
    MotorTerminal u;
    u.voltage_V = kSource;
    u.supply_factor = 1.0;
    u.series_resistance_ohm = 0.5;
    Pair x{DcMotorState{0.1, 100.0, 0.0}, DcMotorState{0.1, 100.0, 0.0}};
    const std::array<CoupledTerminal, 2> c{coupled_terminal(u, 0.1), coupled_terminal(u, 0.1)};
    EXPECT_EQ(c[0].series_resistance_ohm, 0.5);
    CoupledSegment seg;
    double q = 0.0;
    ASSERT_EQ(joint.advance(x, c, kRb, 5.0, seg, q), 5.0);
    const double r = m.resistance_ohm + 0.5 + 2 * kRb;
    const double w = (m.torque_N_m_per_A * kSource - r * m.coulomb_friction_N_m) /
                     (r * m.viscous_friction_N_m_s_per_rad +
                      m.torque_N_m_per_A * m.back_emf_V_s_per_rad);
    EXPECT_NEAR(x[0].speed_rad_s, w, 1e-9 * w);
    EXPECT_NEAR(x[1].speed_rad_s, w, 1e-9 * w);
}

TEST(CoupledMotors, WithoutBatteryResistanceItIsTwoIndependentMotors) {
    const auto p = motors();
    CoupledMotorStepper joint(p[0], p[1]);
    const Pair x0{DcMotorState{0.3, 500.0, 1.0}, DcMotorState{-0.2, -400.0, -2.0}};
    const std::array<Bridge, 2> b{Bridge{true, 1.0}, Bridge{true, -1.0}};
    Pair x = x0;
    CoupledSegment seg;
    double q = 0.0;
    ASSERT_EQ(joint.advance(x, terminals(b, x0), 0.0, 1e-3, seg, q), 1e-3);
    for (std::size_t m = 0; m < 2; ++m) {
        MotorStepper single(p[m]);
        MotorTerminal u;
        u.voltage_V = b[m].sign * (kSource - kDrop);
        u.supply_factor = b[m].sign;
        DcMotorState y = x0[m];
        MotorStepResult r;
        single.advance(y, u, 1e-3, r);
        EXPECT_NEAR(x[m].current_A, y.current_A, 1e-12) << m;
        EXPECT_NEAR(x[m].speed_rad_s, y.speed_rad_s, 1e-9) << m;
        EXPECT_NEAR(x[m].angle_rad, y.angle_rad, 1e-12) << m;
    }
}

TEST(CoupledMotors, ExactSolutionMatchesRk4OfTheCoupledModel) {
    // Motor 1 forward, motor 2 reverse, from a transient state: 2 ms.
    const auto p = motors();
    CoupledMotorStepper joint(p[0], p[1]);
    const Pair x0{DcMotorState{0.05, 900.0, 0.0}, DcMotorState{-0.6, -300.0, 0.0}};
    const std::array<Bridge, 2> b{Bridge{true, 1.0}, Bridge{true, -1.0}};
    Pair x = x0;
    CoupledSegment seg;
    double q = 0.0;
    ASSERT_EQ(joint.advance(x, terminals(b, x0), kRb, 2e-3, seg, q), 2e-3);
    const Rk4Result ref = rk4(p, x0, b, kRb, 2e-3, 20000);
    for (std::size_t m = 0; m < 2; ++m) {
        EXPECT_NEAR(x[m].current_A, ref.x[m].current_A, 1e-10) << m;
        EXPECT_NEAR(x[m].speed_rad_s, ref.x[m].speed_rad_s, 1e-7) << m;
        EXPECT_NEAR(x[m].angle_rad, ref.x[m].angle_rad, 1e-10) << m;
        // state_at() at the end equals the step's end.
        const DcMotorState e = joint.state_at(seg, m, 2e-3);
        EXPECT_NEAR(e.current_A, x[m].current_A, 1e-12) << m;
        EXPECT_NEAR(e.angle_rad, x[m].angle_rad, 1e-12) << m;
    }
    // Charge: integral of s1 I1 + s2 I2 (both bridges draw here).
    EXPECT_NEAR(q, ref.supply_charge_C, 1e-12);
    EXPECT_GT(q, 0.0);
}

TEST(CoupledMotors, SteadyStateMatchesTheHandFormulaWithBothCurrentsInTheBattery) {
    // Identical motors, both forward: V_b = V_s - 2 R_b I, so each motor
    // sees E = V_s - drop behind R_a + 2 R_b, and (viscous + Coulomb)
    //   w = (K_t E - R T_c) / (R F + K_t K_a),  I = (F w + T_c) / K_t.
    const DcMotorParams m;
    CoupledMotorStepper joint(m, m);
    Pair x{DcMotorState{0.1, 100.0, 0.0}, DcMotorState{0.1, 100.0, 0.0}};
    const std::array<Bridge, 2> b{Bridge{}, Bridge{}};
    CoupledSegment seg;
    double q = 0.0;
    ASSERT_EQ(joint.advance(x, terminals(b, x), kRb, 5.0, seg, q), 5.0);  // >> J R / (K_t K_a) = 69 ms
    const double e = kSource - kDrop;
    const double r = m.resistance_ohm + 2 * kRb;
    const double w = (m.torque_N_m_per_A * e - r * m.coulomb_friction_N_m) /
                     (r * m.viscous_friction_N_m_s_per_rad +
                      m.torque_N_m_per_A * m.back_emf_V_s_per_rad);
    EXPECT_NEAR(x[0].speed_rad_s, w, 1e-9 * w);
    EXPECT_NEAR(x[1].speed_rad_s, w, 1e-9 * w);
    const double i = (m.viscous_friction_N_m_s_per_rad * w + m.coulomb_friction_N_m) /
                     m.torque_N_m_per_A;
    EXPECT_NEAR(x[0].current_A, i, 1e-9);
    // Without the coupling (R_b only in series with itself) it runs faster.
    const double w_alone = (m.torque_N_m_per_A * e - (m.resistance_ohm + kRb) * m.coulomb_friction_N_m) /
                           ((m.resistance_ohm + kRb) * m.viscous_friction_N_m_s_per_rad +
                            m.torque_N_m_per_A * m.back_emf_V_s_per_rad);
    EXPECT_GT(w_alone - w, 1.0);  // rad/s: the other motor's current sags this one
}

TEST(CoupledMotors, DiodeCurrentReachingZeroEndsTheSegmentAtItsExactTime) {
    // Motor 1's bridge is off: its current decays through the diodes.
    const auto p = motors();
    CoupledMotorStepper joint(p[0], p[1]);
    const Pair x0{DcMotorState{0.4, 600.0, 0.0}, DcMotorState{0.5, 500.0, 0.0}};
    const std::array<Bridge, 2> b{Bridge{false, 1.0}, Bridge{true, 1.0}};
    Pair x = x0;
    CoupledSegment seg;
    double q = 0.0;
    const double t = joint.advance(x, terminals(b, x0), kRb, 1e-3, seg, q);
    ASSERT_GT(t, 0.0);
    ASSERT_LT(t, 1e-3);
    EXPECT_EQ(x[0].current_A, 0.0);
    // The RK4 reference crosses zero within a step of 1e-8 s of t.
    const Rk4Result before = rk4(p, x0, b, kRb, t - 1e-8, 4000);
    const Rk4Result after = rk4(p, x0, b, kRb, t + 1e-8, 4000);
    EXPECT_GT(before.x[0].current_A, 0.0);
    EXPECT_LT(after.x[0].current_A, 0.0);
    const Rk4Result at = rk4(p, x0, b, kRb, t, 4000);
    EXPECT_NEAR(x[1].current_A, at.x[1].current_A, 1e-10);
    EXPECT_NEAR(x[0].angle_rad, at.x[0].angle_rad, 1e-10);
    EXPECT_NEAR(q, at.supply_charge_C, 1e-13);
    // The motor is then open-circuit: the joint solution refuses to go on.
    const Pair stopped = x;
    EXPECT_EQ(joint.advance(x, terminals(b, x), kRb, 1e-3, seg, q), 0.0);
    EXPECT_EQ(x[0].current_A, stopped[0].current_A);
    EXPECT_EQ(x[1].speed_rad_s, stopped[1].speed_rad_s);
}

TEST(CoupledMotors, SpeedReachingZeroEndsTheSegmentWithTheShaftAtRest) {
    // Motor 2 turns backwards slowly while its bridge drives it forward.
    const auto p = motors();
    CoupledMotorStepper joint(p[0], p[1]);
    const Pair x0{DcMotorState{0.2, 800.0, 0.0}, DcMotorState{0.0, -50.0, 0.0}};
    const std::array<Bridge, 2> b{Bridge{true, 1.0}, Bridge{true, 1.0}};
    Pair x = x0;
    CoupledSegment seg;
    double q = 0.0;
    const double t = joint.advance(x, terminals(b, x0), kRb, 0.01, seg, q);
    ASSERT_GT(t, 0.0);
    ASSERT_LT(t, 0.01);
    EXPECT_EQ(x[1].speed_rad_s, 0.0);
    // (RK4 needs 40000 steps here to place the crossing within 1e-8 s.)
    const Rk4Result before = rk4(p, x0, b, kRb, t - 1e-8, 40000);
    const Rk4Result after = rk4(p, x0, b, kRb, t + 1e-8, 40000);
    EXPECT_LT(before.x[1].speed_rad_s, 0.0);
    EXPECT_GT(after.x[1].speed_rad_s, 0.0);
    EXPECT_NEAR(x[1].angle_rad, before.x[1].angle_rad, 1e-9);
}

TEST(CoupledMotors, ADipThroughZeroAndBackInsideAStepEndsItAtTheZero) {
    // Lightly damped motors (R_a = 0.1 ohm, L_a = 1 mH; eigenvalues
    // -50.6 +- 274i and -87.6 +- 265i): motor 1, braked hard (-17.8 A) at
    // 3670 rad/s and driven forward again, swings through zero near 9.39 ms
    // (to about -2.1 rad/s) and is back at +6 rad/s by the end of a 10 ms
    // step. Both ends are positive, so only the search for the minimum
    // finds it; a bound on the slope alone (the speed falling no faster
    // than it starts to) does not hold for an oscillation past its peak.
    DcMotorParams p;
    p.resistance_ohm = 0.1;
    p.inductance_H = 1e-3;
    CoupledMotorStepper joint(p, p);
    Pair x{DcMotorState{-17.8, 3670.0, 0.0}, DcMotorState{0.5, 1000.0, 0.0}};
    std::array<CoupledTerminal, 2> u{};
    for (CoupledTerminal& t : u) t = CoupledTerminal{1.0, 5.0, false};
    CoupledSegment seg;
    double q = 0.0;
    const double t = joint.advance(x, u, kRb, 0.01, seg, q);
    EXPECT_NEAR(t, 9.3906e-3, 1e-7);
    EXPECT_EQ(x[0].speed_rad_s, 0.0);
    for (int k = 0; k <= 1000; ++k) {  // and it never went below zero before
        ASSERT_GE(joint.state_at(seg, 0, t * k / 1000.0).speed_rad_s, -1e-9) << k;
    }
}

TEST(CoupledMotors, RefusesWhenAShaftIsAtRest) {
    const auto p = motors();
    CoupledMotorStepper joint(p[0], p[1]);
    const Pair x0{DcMotorState{0.1, 0.0, 3.0}, DcMotorState{0.2, 100.0, 0.0}};
    Pair x = x0;
    CoupledSegment seg;
    double q = 7.0;
    EXPECT_EQ(joint.advance(x, terminals({Bridge{}, Bridge{}}, x0), kRb, 1e-4, seg, q), 0.0);
    EXPECT_EQ(x[0].angle_rad, 3.0);
    EXPECT_EQ(x[1].current_A, 0.2);
}

}  // namespace
}  // namespace ddmr::plant
