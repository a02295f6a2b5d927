#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/part_registry.hpp"

namespace ddmr::hil {

std::vector<PartType> builtin_part_types() {
    return {
        shift_register_74hc595_type(),
        // Motor drivers: their order is the board file's list of drivers.
        driver_dir_pwm_type(),
        driver_l298n_type(),
        driver_tb6612_type(),
        driver_drv8833_type(),
        driver_l293d_type(),
        driver_l9110_type(),
        encoder_single_type(),
        encoder_quadrature_type(),
        // Sensors (docs/world.md).
        reflectance_type(),
        marker_type(),
        ultrasonic_hcsr04_type(),
        ir_obstacle_type(),
        bumper_type(),
        servo_type(),
        imu_mpu6050_type(),
    };
}

}  // namespace ddmr::hil
