// l9110: one channel of an L9110 / L9110S (HG7881 modules, the SunFounder
// kit car's driver): IN1 (the module's A-IA or B-IA) and IN2 (A-IB or B-IB),
// PWM on either (speed on one input, the other the direction). No readable
// datasheet of the IC was found: the truth table is the module vendors'
// (../shared/SENSORS.md section 7; plant/motor_driver.cpp).
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_l9110_type() {
    using R = DriverRole;
    return motor_driver_type(
        "l9110", "one channel of an L9110 (HG7881 modules): IA/IB H/L forward, L/H reverse, L/L and H/H brake",
        "no IC datasheet found; Banana Robotics and SunFounder L9110 module tables (SENSORS.md section 7)",
        MotorDriverSpec{plant::DriverType::l9110, "L9110", {R::in1, R::in2}, {}, {}, {}, {}},
        {{R::in1, "IA: the module's A-IA or B-IA"}, {R::in2, "IB: the module's A-IB or B-IB"}});
}

}  // namespace ddmr::hil
