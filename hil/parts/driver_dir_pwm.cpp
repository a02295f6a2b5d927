// dir-pwm: an L298 shield with one direction pin per bridge (the thesis
// robot): PWM drives the bridge's enable, DIR its two inputs through an
// inverter. ST L298 datasheet (Jan. 2000), Figure 6; docs/boards.md.
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_dir_pwm_type() {
    using R = DriverRole;
    return motor_driver_type(
        "dir-pwm", "L298 shield, one direction pin per bridge (PWM H: DIR H forward, L reverse; PWM L: coast)",
        "ST L298 (Jan. 2000), Figure 6 'Bidirectional DC motor control'",
        MotorDriverSpec{plant::DriverType::dir_pwm, "L298 shield", {R::pwm, R::dir}, {}, {}, {R::pwm}, {}},
        {{R::pwm, "the bridge's enable, driven by analogWrite"}, {R::dir, "the direction: high forward, low reverse"}});
}

}  // namespace ddmr::hil
