// tb6612: Toshiba TB6612FNG, one of its two bridges: PWM, IN1, IN2 and the
// module's STBY (which both bridges may share). TB6612FNG datasheet
// (2007-06-30), p. 4 "H-SW Control Function"; docs/boards.md.
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_tb6612_type() {
    using R = DriverRole;
    return motor_driver_type(
        "tb6612", "Toshiba TB6612FNG bridge: IN1/IN2 select, PWM L brakes (slow decay), STBY L coasts",
        "Toshiba TB6612FNG (2007-06-30), p. 4 'H-SW Control Function'",
        MotorDriverSpec{plant::DriverType::tb6612, "TB6612", {R::pwm, R::in1, R::in2, R::stby}, {}, {R::stby}, {R::pwm},
                        {R::stby}},
        {{R::pwm, "PWMA or PWMB"},
         {R::in1, "AIN1 or BIN1"},
         {R::in2, "AIN2 or BIN2"},
         {R::stby, "standby, active low (both bridges may share the pin)"}});
}

}  // namespace ddmr::hil
