// l298n: ST L298 on an L298N module: EN, IN1, IN2 per bridge. ST L298
// datasheet (Jan. 2000), Figure 6 "Bidirectional DC motor control";
// docs/boards.md. EN: high = the module's enable jumper.
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType driver_l298n_type() {
    using R = DriverRole;
    return motor_driver_type(
        "l298n", "ST L298 bridge (L298N modules): EN H, IN1/IN2 H/L forward, L/H reverse, equal brake; EN L coast",
        "ST L298 (Jan. 2000), Figure 6 'Bidirectional DC motor control'",
        MotorDriverSpec{plant::DriverType::l298n, "L298N", {R::en, R::in1, R::in2}, {}, {R::en}, {}, {}},
        {{R::en, "the bridge's enable (ENA or ENB)"}, {R::in1, "input 1 (IN1 or IN3)"}, {R::in2, "input 2 (IN2 or IN4)"}});
}

}  // namespace ddmr::hil
