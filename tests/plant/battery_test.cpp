// Tests for plant/battery: eqs. (18), (19) with the MATLAB listing's numbers
// (V_0 = 6.1 V, 2.5 Ah, R_b = 0.037 ohm, 0.72 V/Ah).
#include "plant/battery.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace ddmr::plant {
namespace {

TEST(Battery, FullPackWithoutLoadReadsTheOpenCircuitVoltage) {
    EXPECT_DOUBLE_EQ(terminal_voltage_V(BatteryParams{}, BatteryState{}, 0.0), 6.1);
}

TEST(Battery, SagsWithChargeAndCurrentPerEq19) {
    // 0.5 Ah drawn (1800 C), 0.3 A flowing:
    // 6.1 - 0.72*0.5 - 0.037*0.3 = 6.1 - 0.36 - 0.0111 = 5.7289 V
    EXPECT_NEAR(terminal_voltage_V(BatteryParams{}, BatteryState{1800.0}, 0.3), 5.7289, 1e-12);
    // Current returned through the flyback diodes (negative) raises it:
    // 6.1 + 0.037*0.2 = 6.1074 V
    EXPECT_NEAR(terminal_voltage_V(BatteryParams{}, BatteryState{}, -0.2), 6.1074, 1e-12);
}

TEST(Battery, NeverReadsBelowZero) {
    // 10 Ah drawn: 6.1 - 7.2 < 0 -> 0.
    EXPECT_EQ(terminal_voltage_V(BatteryParams{}, BatteryState{36000.0}, 0.0), 0.0);
}

TEST(Battery, StateOfCharge) {
    // 0.5 Ah of 2.5 Ah drawn: 80 % left.
    EXPECT_NEAR(state_of_charge(BatteryParams{}, BatteryState{1800.0}), 0.8, 1e-12);
    EXPECT_EQ(charge_derivative_A(0.25), 0.25);  // eq. (18): dq/dt = I_1 + I_2
}

TEST(Battery, RejectsInvalidParameters) {
    BatteryParams p;
    p.capacity_Ah = 0.0;
    EXPECT_THROW(validate(p, "battery"), std::invalid_argument);
    p = BatteryParams{};
    p.internal_resistance_ohm = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(validate(p, "battery"), std::invalid_argument);
    EXPECT_NO_THROW(validate(BatteryParams{}, "battery"));
}

}  // namespace
}  // namespace ddmr::plant
