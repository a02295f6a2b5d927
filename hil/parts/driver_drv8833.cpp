// drv8833: TI DRV8833, one of its two bridges: IN1, IN2 (either may carry
// PWM) and nSLEEP (breakout boards pull it up; both bridges may share it).
// TI SLVSAR1E, section 7.3.2 Tables 1 and 2; docs/boards.md.
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_drv8833_type() {
    using R = DriverRole;
    return motor_driver_type(
        "drv8833", "TI DRV8833 bridge: IN1/IN2 H/L forward, L/H reverse, H/H brake, L/L coast; SLEEP L coasts",
        "TI SLVSAR1E, section 7.3.2 Tables 1 and 2",
        MotorDriverSpec{plant::DriverType::drv8833, "DRV8833", {R::in1, R::in2}, {R::sleep}, {R::sleep}, {}, {R::sleep}},
        {{R::in1, "AIN1 or BIN1"}, {R::in2, "AIN2 or BIN2"}, {R::sleep, "nSLEEP, active low (left out: pulled up)"}});
}

}  // namespace ddmr::hil
