// Tests for plant/motor_stepper: the exact piecewise solution of one motor.
// Default motor 1 parameters (see dc_motor_test.cpp for the list).
#include "plant/motor_stepper.hpp"

#include <gtest/gtest.h>

#include "support/motor_terminals.hpp"

#include <cmath>

namespace ddmr::plant {
namespace {

using test::driven;

MotorTerminal open_bridge() {
    MotorTerminal u;
    u.kind = MotorTerminal::Kind::open;
    u.clamp_V = 7.7;
    return u;
}

/// Classic RK4 on the derivative function (the reference integrator).
DcMotorState rk4(const DcMotorParams& p, DcMotorState x, const MotorTerminal& u, double t,
                 int n) {
    const double h = t / n;
    auto add = [](DcMotorState s, const DcMotorDerivative& d, double k) {
        s.current_A += k * d.current_A_s;
        s.speed_rad_s += k * d.speed_rad_s2;
        s.angle_rad += k * d.angle_rad_s;
        return s;
    };
    for (int k = 0; k < n; ++k) {
        const DcMotorDerivative k1 = derivative(p, x, u);
        const DcMotorDerivative k2 = derivative(p, add(x, k1, h / 2), u);
        const DcMotorDerivative k3 = derivative(p, add(x, k2, h / 2), u);
        const DcMotorDerivative k4 = derivative(p, add(x, k3, h), u);
        x.current_A += h / 6 * (k1.current_A_s + 2 * k2.current_A_s + 2 * k3.current_A_s + k4.current_A_s);
        x.speed_rad_s += h / 6 * (k1.speed_rad_s2 + 2 * k2.speed_rad_s2 + 2 * k3.speed_rad_s2 + k4.speed_rad_s2);
        x.angle_rad += h / 6 * (k1.angle_rad_s + 2 * k2.angle_rad_s + 2 * k3.angle_rad_s + k4.angle_rad_s);
    }
    return x;
}

TEST(MotorStepper, ExactSolutionMatchesRk4OfTheDerivative) {
    const DcMotorParams p;
    MotorStepper s(p);
    DcMotorState x{0.1, 300.0, 0.0};
    MotorStepResult r;
    s.advance(x, driven(4.7), 0.01, r);  // one 10 ms step, no event (w stays > 0)
    const DcMotorState ref = rk4(p, DcMotorState{0.1, 300.0, 0.0}, driven(4.7), 0.01, 100000);
    EXPECT_NEAR(x.current_A, ref.current_A, 1e-10);
    EXPECT_NEAR(x.speed_rad_s, ref.speed_rad_s, 1e-8);
    EXPECT_NEAR(x.angle_rad, ref.angle_rad, 1e-10);
    EXPECT_EQ(r.segment_count, 1u);
}

TEST(MotorStepper, StepLengthDoesNotChangeTheResult) {
    // Exact discretisation: 1 step of 20 ms == 2000 steps of 10 us, events included
    // (start at rest: stiction, then breakaway inside the first step).
    const DcMotorParams p;
    MotorStepper a(p), b(p);
    DcMotorState xa, xb;
    MotorStepResult r;
    a.advance(xa, driven(4.7), 0.02, r);
    for (int k = 0; k < 2000; ++k) b.advance(xb, driven(4.7), 1e-5, r);
    EXPECT_NEAR(xa.current_A, xb.current_A, 1e-9);
    EXPECT_NEAR(xa.speed_rad_s, xb.speed_rad_s, 1e-7);
    EXPECT_NEAR(xa.angle_rad, xb.angle_rad, 1e-8);
}

TEST(MotorStepper, ReachesTheSteadyStateFormula) {
    const DcMotorParams p;
    MotorStepper s(p);
    DcMotorState x;
    MotorStepResult r;
    s.advance(x, driven(4.7), 2.0, r);  // 2 s = 31 slow time constants
    // w = (K_t V - R_a T_c) / (R_a F + K_t K_a) = 1057.07 rad/s (dc_motor_test.cpp)
    EXPECT_NEAR(x.speed_rad_s, steady_state_speed_rad_s(p, 4.7), 1e-6);
    EXPECT_NEAR(x.speed_rad_s, 1057.07, 0.01);
    // I = (F w + T_c) / K_t = (2.2e-7*1057.07 + 2.3e-4) / 0.00384 = 0.12046 A
    EXPECT_NEAR(x.current_A, 0.12046, 1e-5);
}

TEST(MotorStepper, TimeConstantsOfTheStepResponse) {
    DcMotorParams p;
    p.coulomb_friction_N_m = 0.0;  // pure eq. (9e) for this test
    MotorStepper s(p);
    // Hand formulas: electrical tau_e = L_a / R_a = 2.3e-3 / 5.32 = 0.4323 ms;
    // mechanical tau_m = J R_a / (K_t K_a + R_a F)
    //   = 1.9e-7*5.32 / (1.47456e-5 + 1.1704e-6) = 63.51 ms.
    // The eigenvalues of A are close to -1/tau_e and -1/tau_m because tau_m >> tau_e.
    EXPECT_NEAR(-1.0 / s.fast_eigenvalue_real(), 0.4323e-3, 0.01 * 0.4323e-3);
    EXPECT_NEAR(-1.0 / s.slow_eigenvalue_real(), 63.51e-3, 0.01 * 63.51e-3);

    // Measured on the simulated step response (V = 4.7 V from rest):
    // current to 63.2 % of V/R_a = 0.8835 A within ~tau_e (back-EMF still ~0),
    // speed to 63.2 % of its final value within ~tau_m.
    const double v = 4.7;
    const double w_final = steady_state_speed_rad_s(p, v);
    DcMotorState x;
    MotorStepResult r;
    double t = 0.0, t_i = -1.0, t_w = -1.0;
    const double h = 1e-6;
    while (t < 0.3) {
        s.advance(x, driven(v), h, r);
        t += h;
        if (t_i < 0 && x.current_A >= (1 - std::exp(-1.0)) * v / p.resistance_ohm) t_i = t;
        if (t_w < 0 && x.speed_rad_s >= (1 - std::exp(-1.0)) * w_final) t_w = t;
    }
    EXPECT_NEAR(t_i, 0.4323e-3, 0.05 * 0.4323e-3);
    EXPECT_NEAR(t_w, 63.51e-3, 0.02 * 63.51e-3);
}

TEST(MotorStepper, StaysStuckBelowTheBreakawayVoltage) {
    const DcMotorParams p;
    MotorStepper s(p);
    // Breakaway voltage R_a T_c / K_t = 5.32*2.3e-4/0.00384 = 0.3186 V.
    DcMotorState x;
    MotorStepResult r;
    s.advance(x, driven(0.30), 1.0, r);
    EXPECT_EQ(x.speed_rad_s, 0.0);
    EXPECT_EQ(x.angle_rad, 0.0);
    EXPECT_NEAR(x.current_A, 0.30 / 5.32, 1e-9);  // 0.05639 A, all through R_a
    // Slightly above: w = (0.00384*0.35 - 5.32*2.3e-4) / 1.5916e-5 = 7.5647 rad/s.
    DcMotorState y;
    s.advance(y, driven(0.35), 3.0, r);
    EXPECT_NEAR(y.speed_rad_s, 7.5647, 1e-3);
}

TEST(MotorStepper, CoastingStopsInFiniteTime) {
    const DcMotorParams p;
    MotorStepper s(p);
    // Open circuit, I = 0, w0 = 1000 rad/s: J w' = -F w - T_c.
    // Stops at t = (J/F) ln(1 + F w0 / T_c) = 0.86364 * ln(1.95652) = 0.579645 s
    // after turning (J/F)(w0 - (T_c/F) ln(1 + F w0/T_c)) = 257.644 rad.
    DcMotorState x{0.0, 1000.0, 0.0};
    MotorStepResult r;
    s.advance(x, open_bridge(), 0.5796, r);
    EXPECT_GT(x.speed_rad_s, 0.0);
    s.advance(x, open_bridge(), 0.0001, r);
    EXPECT_EQ(x.speed_rad_s, 0.0);
    EXPECT_NEAR(r.segments[0].duration_s, 0.579645 - 0.5796, 1e-6);
    EXPECT_NEAR(x.angle_rad, 257.644, 1e-3);
    s.advance(x, open_bridge(), 1.0, r);  // and stays stopped
    EXPECT_EQ(x.speed_rad_s, 0.0);
    EXPECT_NEAR(x.angle_rad, 257.644, 1e-3);
}

TEST(MotorStepper, CoastFollowsTheFrictionDecayAndStopsAtTheHandWorkedTime) {
    const DcMotorParams p;
    MotorStepper s(p);
    // J/F = 0.863636 s, T_c/F = 1045.45 rad/s. From w0 = 1000 rad/s:
    //   w(t) = -1045.45 + 2045.45 e^{-t/0.863636}: w(0.1) = 776.3555 rad/s,
    //   angle(0.1) = -104.545 + 2045.45 x 0.863636 (1 - e^{-0.1/0.863636}) = 88.60203 rad;
    //   w = 0 at t = 0.863636 ln(1 + 1000/1045.45) = 0.5796453 s.
    const DcMotorState x{0.0, 1000.0, 0.0};
    MotorSegment seg;
    s.coast(x, 0.1, seg);
    EXPECT_EQ(seg.regime, MotorRegime::coasting);
    EXPECT_EQ(seg.duration_s, 0.1);
    EXPECT_NEAR(seg.end.speed_rad_s, 776.3555462509, 1e-9);
    EXPECT_NEAR(seg.end.angle_rad, 88.6020282379, 1e-9);
    EXPECT_EQ(seg.end.current_A, 0.0);
    s.coast(x, 1.0, seg);  // stops inside: the segment ends there, at rest
    EXPECT_NEAR(seg.duration_s, 0.5796453274, 1e-9);
    EXPECT_EQ(seg.end.speed_rad_s, 0.0);
    EXPECT_NEAR(seg.end.angle_rad, 257.644, 1e-3);
    // Backwards it is the mirror image.
    s.coast(DcMotorState{0.0, -1000.0, 0.0}, 0.1, seg);
    EXPECT_NEAR(seg.end.speed_rad_s, -776.3555462509, 1e-9);
    EXPECT_NEAR(seg.end.angle_rad, -88.6020282379, 1e-9);
    // At rest it stays at rest.
    s.coast(DcMotorState{0.0, 0.0, 3.0}, 0.1, seg);
    EXPECT_EQ(seg.regime, MotorRegime::stopped);
    EXPECT_EQ(seg.end.speed_rad_s, 0.0);
    EXPECT_EQ(seg.end.angle_rad, 3.0);
}

TEST(MotorStepper, BridgeOffCurrentFallsToZeroAndStaysThere) {
    const DcMotorParams p;
    MotorStepper s(p);
    DcMotorState x{0.2, 500.0, 0.0};
    MotorStepResult r;
    s.advance(x, open_bridge(), 1e-3, r);
    // dI/dt starts at -(7.7 + 5.32*0.2 + 0.00384*500)/2.3e-3 = -4645 A/s and ends at
    // -(7.7 + 1.92)/2.3e-3 = -4183 A/s, so I = 0.2 A reaches 0 after 43-48 us.
    ASSERT_GE(r.segment_count, 2u);
    EXPECT_EQ(r.segments[0].regime, MotorRegime::moving);
    EXPECT_GT(r.segments[0].duration_s, 0.2 / 4645.0);
    EXPECT_LT(r.segments[0].duration_s, 0.2 / 4183.0);
    EXPECT_EQ(r.segments[1].regime, MotorRegime::coasting);
    EXPECT_EQ(x.current_A, 0.0);  // exactly: discontinuous conduction
    EXPECT_GT(x.speed_rad_s, 490.0);
    // The charge went back into the battery: supply charge = -integral of I
    // ~ -0.5 * 0.2 A * 45 us = -4.5e-6 C.
    EXPECT_NEAR(r.supply_charge_C, -r.charge_C, 1e-15);
    EXPECT_NEAR(r.charge_C, 4.5e-6, 0.3e-6);
}

TEST(MotorStepper, ReversalThroughZeroSplitsTheStep) {
    const DcMotorParams p;
    MotorStepper s(p);
    // Turning forward at 500 rad/s, then -4.7 V: it brakes, stops, reverses.
    DcMotorState x{0.0, 500.0, 0.0};
    MotorStepResult r;
    s.advance(x, driven(-4.7), 0.2, r);
    bool has_zero = false;
    for (std::size_t k = 0; k + 1 < r.segment_count; ++k) {
        if (r.segments[k].end.speed_rad_s == 0.0) has_zero = true;
    }
    EXPECT_TRUE(has_zero);
    EXPECT_LT(x.speed_rad_s, -500.0);
    // Compare with RK4 of the derivative (stiction crossing only lasts an instant).
    const DcMotorState ref = rk4(p, DcMotorState{0.0, 500.0, 0.0}, driven(-4.7), 0.2, 400000);
    EXPECT_NEAR(x.speed_rad_s, ref.speed_rad_s, 1e-3);
    EXPECT_NEAR(x.angle_rad, ref.angle_rad, 1e-4);
}

TEST(MotorStepper, ChargeIsTheIntegralOfTheCurrent) {
    const DcMotorParams p;
    MotorStepper s(p);
    DcMotorState x;
    MotorStepResult r;
    s.advance(x, driven(4.7), 0.05, r);
    const double exact = r.charge_C;
    // Trapezoid rule on 1 us samples of the same solution.
    MotorStepper s2(p);
    DcMotorState y;
    double q = 0.0;
    for (int k = 0; k < 50000; ++k) {
        const double i0 = y.current_A;
        s2.advance(y, driven(4.7), 1e-6, r);
        q += 0.5 * (i0 + y.current_A) * 1e-6;
    }
    EXPECT_NEAR(exact, q, 1e-9);
    EXPECT_GT(exact, 0.01);  // ~0.5 A average for 50 ms: not a vacuous comparison
}

}  // namespace
}  // namespace ddmr::plant
