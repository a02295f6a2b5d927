// Tests for plant/dc_motor: the derivative function, eqs. (9a), (9b) with
// Coulomb friction, and the steady-state formula. Expected values are worked
// out by hand from the default parameters of motor 1:
//   R_a = 5.32 ohm, L_a = 2.3e-3 H, K_a = K_t = 0.00384, J = 1.9e-7 kg m^2,
//   F = 2.2e-7 N m s/rad, T_c = 2.3e-4 N m.
#include "plant/dc_motor.hpp"

#include <gtest/gtest.h>

#include "support/motor_terminals.hpp"

#include <cmath>

namespace ddmr::plant {
namespace {

using test::driven;

TEST(DcMotor, DerivativeWhileMovingIsEq9aAnd9b) {
    const DcMotorParams p;
    const DcMotorState x{0.2, 500.0, 0.0};
    const DcMotorDerivative d = derivative(p, x, driven(4.7));
    // dI/dt = (4.7 - 5.32*0.2 - 0.00384*500) / 2.3e-3 = 1.716 / 2.3e-3 = 746.087 A/s
    EXPECT_NEAR(d.current_A_s, 746.087, 1e-3);
    // dw/dt = (0.00384*0.2 - 2.2e-7*500 - 2.3e-4) / 1.9e-7 = 4.28e-4 / 1.9e-7 = 2252.63 rad/s^2
    EXPECT_NEAR(d.speed_rad_s2, 2252.63, 1e-2);
    EXPECT_DOUBLE_EQ(d.angle_rad_s, 500.0);
}

TEST(DcMotor, FrictionOpposesMotionInReverse) {
    const DcMotorParams p;
    // Mirror image of the case above: every derivative changes sign.
    const DcMotorDerivative d = derivative(p, DcMotorState{-0.2, -500.0, 0.0}, driven(-4.7));
    EXPECT_NEAR(d.current_A_s, -746.087, 1e-3);
    EXPECT_NEAR(d.speed_rad_s2, -2252.63, 1e-2);
}

TEST(DcMotor, StictionHoldsTheShaftBelowTheCoulombTorque) {
    const DcMotorParams p;
    // K_t I = 0.00384 * 0.05 = 1.92e-4 < T_c = 2.3e-4: stuck, dw/dt = 0.
    EXPECT_EQ(derivative(p, DcMotorState{0.05, 0.0, 0.0}, driven(1.0)).speed_rad_s2, 0.0);
    // K_t I = 0.00384 * 0.1 = 3.84e-4 > T_c: (3.84e-4 - 2.3e-4) / 1.9e-7 = 810.53 rad/s^2.
    EXPECT_NEAR(derivative(p, DcMotorState{0.1, 0.0, 0.0}, driven(1.0)).speed_rad_s2, 810.526, 1e-3);
}

TEST(DcMotor, OpenBridgeClampsThroughTheDiodesThenOpens) {
    const DcMotorParams p;
    MotorTerminal open;
    open.kind = MotorTerminal::Kind::open;
    open.clamp_V = 7.7;  // 6.1 V + 2 x 0.8 V
    // I = 0.2 > 0: V = -7.7, dI/dt = (-7.7 - 1.064 - 1.92) / 2.3e-3 = -4645.2 A/s
    EXPECT_NEAR(derivative(p, DcMotorState{0.2, 500.0, 0.0}, open).current_A_s, -4645.22, 1e-2);
    // I = 0: open circuit, the current stays 0 and the shaft only slows down:
    // dw/dt = (-2.2e-7*500 - 2.3e-4) / 1.9e-7 = -1789.47 rad/s^2
    const DcMotorDerivative d = derivative(p, DcMotorState{0.0, 500.0, 0.0}, open);
    EXPECT_EQ(d.current_A_s, 0.0);
    EXPECT_NEAR(d.speed_rad_s2, -1789.47, 1e-2);
}

TEST(DcMotor, SteadyStateSpeedFormula) {
    const DcMotorParams p;
    // w = (K_t V - R_a T_c) / (R_a F + K_t K_a)
    //   = (0.00384*4.7 - 5.32*2.3e-4) / (5.32*2.2e-7 + 0.00384^2)
    //   = 0.0168244 / 1.59160e-5 = 1057.07 rad/s
    EXPECT_NEAR(steady_state_speed_rad_s(p, 4.7), 1057.07, 0.01);
    // Below the breakaway voltage R_a T_c / K_t = 0.3186 V it does not turn.
    EXPECT_EQ(steady_state_speed_rad_s(p, 0.3), 0.0);
    // The derivative vanishes there (consistency of the two functions).
    const double w = steady_state_speed_rad_s(p, 4.7);
    const double i = (p.viscous_friction_N_m_s_per_rad * w + p.coulomb_friction_N_m) /
                     p.torque_N_m_per_A;
    const DcMotorDerivative d = derivative(p, DcMotorState{i, w, 0.0}, driven(4.7));
    EXPECT_NEAR(d.current_A_s, 0.0, 1e-9);
    EXPECT_NEAR(d.speed_rad_s2, 0.0, 1e-6);
}

TEST(DcMotor, RpmConversions) {
    // 210 RPM = 210 * 2 pi / 60 = 21.9911 rad/s; x 48 = 1055.58 rad/s at the motor.
    EXPECT_NEAR(rpm_to_rad_s(210.0), 21.9911, 1e-4);
    EXPECT_NEAR(rad_s_to_rpm(rpm_to_rad_s(210.0)), 210.0, 1e-12);
    EXPECT_NEAR(wheel_speed_rad_s(DcMotorParams{}, 1055.575), 21.9911, 1e-4);
}

}  // namespace
}  // namespace ddmr::plant
