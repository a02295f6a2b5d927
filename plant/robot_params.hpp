#pragma once
// All parameters of the robot plant, one validated struct per part, plus the
// stepping configuration. Motor/encoder index 0 is motor 1 (RIGHT wheel,
// encoder on pin 2), index 1 is motor 2 (LEFT wheel, pin 3).
//
// The embedded defaults (default_robot_params) equal plant/params/default.yaml,
// which documents each value's unit, range and source (a test checks both).

#include <array>
#include <string>

#include "plant/battery.hpp"
#include "plant/dc_motor.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/hall_encoder.hpp"
#include "plant/l298_driver.hpp"
#include "plant/param_spec.hpp"

namespace ddmr::plant {

/// Configuration of the fixed-step stepper in Robot::step (robot.hpp).
struct StepperConfig {
    /// Longest internal step [s], (0, 0.01]. Robot::step(dt) splits dt into
    /// ceil(dt / max_step_s) equal steps. While both shafts turn, the motors
    /// and the battery between them are solved exactly, so this bounds only
    /// the arc approximation of the pose (and how long the source voltage
    /// V_0 - k AH is held). 1e-4 s (1600 AVR cycles): see robot_test.cpp's
    /// halving test and docs/plant.md.
    double max_step_s = 1e-4;
    /// Longest piece of a step in which a motor changes regime (sticks,
    /// breaks away, or its diode current reaches zero) [s], (0, 0.01]. Such
    /// a step is solved motor by motor with the battery coupling held over
    /// each piece. 2e-5 s (320 AVR cycles).
    double event_step_s = 2e-5;
};

const std::array<Field<StepperConfig>, 2>& stepper_fields();
void validate(const StepperConfig& p, const char* prefix);

struct RobotParams {
    std::array<DcMotorParams, 2> motor{};
    L298Params driver{};
    BatteryParams battery{};
    std::array<HallEncoderParams, 2> encoder{};
    DiffDriveParams kinematics{};
    StepperConfig stepper{};
};

/// The embedded defaults: Table 2, the firmware and our estimates (default.yaml).
RobotParams default_robot_params();

/// Throws std::invalid_argument naming "section.key", its value and its range.
void validate(const RobotParams& p);

/// Field-by-field equality (exact).
bool operator==(const RobotParams& a, const RobotParams& b);
inline bool operator!=(const RobotParams& a, const RobotParams& b) { return !(a == b); }

/// Calls v(section_name, part, field_table) for each part, in file order.
template <class R, class V>
void for_each_section(R& p, V&& v) {
    v("motor1", p.motor[0], dc_motor_fields());
    v("motor2", p.motor[1], dc_motor_fields());
    v("driver", p.driver, l298_fields());
    v("battery", p.battery, battery_fields());
    v("encoder1", p.encoder[0], hall_encoder_fields());
    v("encoder2", p.encoder[1], hall_encoder_fields());
    v("kinematics", p.kinematics, diff_drive_fields());
    v("integration", p.stepper, stepper_fields());
}

}  // namespace ddmr::plant
