#pragma once
// The built-in part types, one function per part file (the explicit list that
// static linking keeps: builtin_parts.cpp). To add a part: write its file
// with a `PartType <name>_type()`, declare it here and list it in
// builtin_parts.cpp (docs/architecture.md, "How to add a part").

#include "hil/parts/part.hpp"

namespace ddmr::hil {

PartType shift_register_74hc595_type();  // shift_register_74hc595.cpp
PartType driver_dir_pwm_type();           // driver_dir_pwm.cpp
PartType driver_l298n_type();             // driver_l298n.cpp
PartType driver_tb6612_type();            // driver_tb6612.cpp
PartType driver_drv8833_type();           // driver_drv8833.cpp
PartType driver_l293d_type();             // driver_l293d.cpp
PartType imu_mpu6050_type();              // imu_mpu6050.cpp
PartType driver_l9110_type();             // driver_l9110.cpp
PartType encoder_single_type();           // encoder_single.cpp
PartType encoder_quadrature_type();       // encoder_quadrature.cpp
PartType bumper_type();                   // bumper.cpp
PartType ir_obstacle_type();              // ir_obstacle.cpp
PartType marker_type();                   // marker.cpp
PartType reflectance_type();              // reflectance.cpp
PartType servo_type();                    // servo.cpp
PartType ultrasonic_hcsr04_type();        // ultrasonic_hcsr04.cpp

}  // namespace ddmr::hil
