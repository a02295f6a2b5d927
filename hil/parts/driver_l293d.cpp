// l293d: half a TI L293D, one bridge: EN (1,2EN or 3,4EN), IN1 (1A or 3A),
// IN2 (2A or 4A). On the Adafruit Motor Shield v1 the inputs come from the
// shield's 74HC595 (IN1: shield.Q2) and EN from a timer's PWM pin. TI SLRS008,
// function table and Figure 5 "Bidirectional DC motor control"; DRIVERS.md 4.
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_l293d_type() {
    using R = DriverRole;
    return motor_driver_type(
        "l293d", "half a TI L293D (one bridge): EN H, IN1/IN2 H/L forward, L/H reverse, equal brake; EN L coast",
        "TI L293, L293D (SLRS008), function table and Figure 5 'Bidirectional DC motor control'",
        MotorDriverSpec{plant::DriverType::l293d, "L293D", {R::en, R::in1, R::in2}, {}, {R::en}, {}, {}},
        {{R::en, "the enable, 1,2EN or 3,4EN"}, {R::in1, "input 1A or 3A"}, {R::in2, "input 2A or 4A"}});
}

}  // namespace ddmr::hil
