#include "plant/imu_kinematics.hpp"

#include <cmath>

namespace ddmr::plant {
namespace {

/// A vector in the robot's frame, in the chip's axes.
Eigen::Vector3d to_chip(const Eigen::Vector3d& v, const ImuMount& m) {
    const double c = std::cos(m.yaw_rad), s = std::sin(m.yaw_rad);
    Eigen::Vector3d out(c * v.x() + s * v.y(), -s * v.x() + c * v.y(), v.z());
    if (m.z_down) {
        out.y() = -out.y();
        out.z() = -out.z();
    }
    return out;
}

}  // namespace

ImuReading imu_reading(const Pose& p0, const Pose& p1, const Pose& p2, double dt_s, const ImuMount& mount) {
    const double w1 = (p1.theta_rad - p0.theta_rad) / dt_s;
    const double w2 = (p2.theta_rad - p1.theta_rad) / dt_s;
    const double alpha = (w2 - w1) / dt_s;
    // The axle middle's acceleration in the world, then in the robot's frame.
    const Eigen::Vector2d a_world((p2.x_m - 2.0 * p1.x_m + p0.x_m) / (dt_s * dt_s),
                                  (p2.y_m - 2.0 * p1.y_m + p0.y_m) / (dt_s * dt_s));
    // The second difference is the acceleration at p1: turned into p1's frame.
    const double c = std::cos(p1.theta_rad), s = std::sin(p1.theta_rad);
    Eigen::Vector2d a(c * a_world.x() + s * a_world.y(), -s * a_world.x() + c * a_world.y());
    // The sensor point r: tangential alpha x r, centripetal -w^2 r (w at p1).
    const double w_mid = (p2.theta_rad - p0.theta_rad) / (2.0 * dt_s);
    const Eigen::Vector2d r(mount.x_m, mount.y_m);
    a += alpha * Eigen::Vector2d(-r.y(), r.x()) - w_mid * w_mid * r;
    ImuReading out;
    out.gyro_rad_s = to_chip(Eigen::Vector3d(0.0, 0.0, w2), mount);
    out.accel_m_s2 = to_chip(Eigen::Vector3d(a.x(), a.y(), kStandardGravity_m_s2), mount);
    return out;
}

}  // namespace ddmr::plant
