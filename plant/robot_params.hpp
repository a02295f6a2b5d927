#pragma once
// All parameters of the robot plant, one validated struct per part, plus the
// stepping configuration. Motor/encoder index 0 is motor 1 (RIGHT wheel),
// index 1 is motor 2 (LEFT wheel).
//
// The embedded defaults (default_robot_params) equal plant/params/default.yaml,
// which documents each value's unit, range and source (a test checks both).
// Two things are not in a plant file because the board file decides them
// (the HIL sets them): which chip drives each motor (`chip`) and how many
// outputs each encoder has (HallEncoderParams::channels).

#include <array>
#include <cstddef>
#include <string>

#include "plant/battery.hpp"
#include "plant/body_contact.hpp"
#include "plant/dc_motor.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/hall_encoder.hpp"
#include "plant/bridge_driver.hpp"
#include "plant/motor_driver.hpp"
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
    /// The L298's bridges (YAML section `driver:`, the name it had when the
    /// L298 was the only chip, so older plant files load unchanged).
    BridgeParams driver = default_bridge_params(DriverChip::l298);
    BridgeParams tb6612 = default_bridge_params(DriverChip::tb6612);    ///< YAML `tb6612:`
    BridgeParams drv8833 = default_bridge_params(DriverChip::drv8833);  ///< YAML `drv8833:`
    BridgeParams l293d = default_bridge_params(DriverChip::l293d);      ///< YAML `l293d:`
    BridgeParams l9110 = default_bridge_params(DriverChip::l9110);      ///< YAML `l9110:`
    /// The chip driving each motor: selects one of the five above. Not a
    /// YAML key: the HIL sets it from the board file. Default: the thesis's L298 shield.
    std::array<DriverChip, 2> chip{DriverChip::l298, DriverChip::l298};
    BatteryParams battery{};
    std::array<HallEncoderParams, 2> encoder{};
    DiffDriveParams kinematics{};
    BodyParams body{};  ///< the chassis footprint and what the wheels do at a wall (YAML `body:`)
    StepperConfig stepper{};
};

/// The embedded defaults: Table 2, the firmware and our estimates (default.yaml).
RobotParams default_robot_params();

/// Throws std::invalid_argument naming "section.key", its value and its range.
void validate(const RobotParams& p);

/// The bridge parameters of the chip driving `motor` (0 or 1). Inline: it
/// runs twice per plant step.
inline const BridgeParams& bridge_params(const RobotParams& p, std::size_t motor) {
    switch (p.chip[motor]) {
        case DriverChip::tb6612: return p.tb6612;
        case DriverChip::drv8833: return p.drv8833;
        case DriverChip::l293d: return p.l293d;
        case DriverChip::l9110: return p.l9110;
        case DriverChip::l298: break;
    }
    return p.driver;
}

/// Field-by-field equality (exact), the board-set fields (chip, encoder
/// channels) included.
bool operator==(const RobotParams& a, const RobotParams& b);
inline bool operator!=(const RobotParams& a, const RobotParams& b) { return !(a == b); }

/// Calls v(section_name, part, field_table) for each part, in file order.
template <class R, class V>
void for_each_section(R& p, V&& v) {
    v("motor1", p.motor[0], dc_motor_fields());
    v("motor2", p.motor[1], dc_motor_fields());
    v("driver", p.driver, bridge_fields());
    v("tb6612", p.tb6612, bridge_fields());
    v("drv8833", p.drv8833, bridge_fields());
    v("l293d", p.l293d, bridge_fields());
    v("l9110", p.l9110, bridge_fields());
    v("battery", p.battery, battery_fields());
    v("encoder1", p.encoder[0], hall_encoder_fields());
    v("encoder2", p.encoder[1], hall_encoder_fields());
    v("kinematics", p.kinematics, diff_drive_fields());
    v("body", p.body, body_fields());
    v("integration", p.stepper, stepper_fields());
}

}  // namespace ddmr::plant
