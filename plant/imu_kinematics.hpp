#pragma once
// What an IMU fixed to the chassis senses, from the robot's planar motion
// (../shared/SENSORS.md section 5; docs/world.md "imu"):
//   - the angular rate: the robot turns about the vertical only, so the
//     rate is (0, 0, d theta / dt) in the robot's frame (x forward, y left,
//     z up);
//   - the specific force an accelerometer reads, f = a - g: at rest it reads
//     +1 g on z (g points down). a is the sensor point's acceleration: the
//     axle middle's, plus alpha x r (tangential) and omega x (omega x r)
//     (centripetal) for a sensor at r from it.
// Rates and accelerations come from three successive poses a fixed time
// apart (finite differences over the plant's step, so a push or a contact
// shows as the chip would feel it): the rate over the last step, the
// acceleration at the middle pose (one step, 62.5 us, behind).
// Then the chip's own axes: turned by `yaw_rad` about z from the robot's
// (its X axis at yaw_rad counter-clockwise from forward), and mounted upside
// down (`z_down`: turned 180 degrees about its X axis, so Y and Z flip).

#include <Eigen/Core>

#include "plant/diff_drive_kinematics.hpp"

namespace ddmr::plant {

inline constexpr double kStandardGravity_m_s2 = 9.80665;

/// Where the chip sits and how it is turned.
struct ImuMount {
    double x_m = 0.0, y_m = 0.0;  ///< from the axle's middle, robot frame
    double yaw_rad = 0.0;         ///< the chip's X axis from forward, counter-clockwise
    bool z_down = false;          ///< mounted upside down (Z points at the floor)
};

/// One reading in the chip's axes: angular rate [rad/s], specific force [m/s^2].
struct ImuReading {
    Eigen::Vector3d gyro_rad_s = Eigen::Vector3d::Zero();
    Eigen::Vector3d accel_m_s2 = Eigen::Vector3d::Zero();
};

/// The reading at the time of `p2`, from poses p0, p1, p2 taken `dt_s` apart (> 0).
ImuReading imu_reading(const Pose& p0, const Pose& p1, const Pose& p2, double dt_s, const ImuMount& mount);

}  // namespace ddmr::plant
