#pragma once
// A purely kinematic robot: the wheels turn at the commanded speeds at once
// (no motors, no battery, no encoders, no speed limit). The plant of
// Kanayama's proof of eq. (16), for checking the Lyapunov function.
//
//   (wheel speeds held over dt) => eqs. (5a), (5b), (10), exact arc
//
// Outputs mirror plant::Robot's where they exist; currents are 0, the
// battery stays at its open-circuit voltage, no encoder edges.

#include <array>
#include <cstddef>

#include "plant/diff_drive_kinematics.hpp"

namespace ddmr::hostsim {

class KinematicPlant {
  public:
    explicit KinematicPlant(const plant::DiffDriveParams& p) : params_(p) {}

    /// Wheel speeds held from now on [rad/s]: right (motor 1), left (motor 2).
    void set_wheel_speeds(double right_rad_s, double left_rad_s) {
        wheel_rad_s_ = {right_rad_s, left_rad_s};
    }
    /// Advances by dt_s along the exact arc of the held wheel speeds.
    void step(double dt_s);

    [[nodiscard]] double time_s() const { return t_s_; }
    [[nodiscard]] const plant::Pose& pose() const { return pose_; }
    [[nodiscard]] double wheel_speed_rad_s(std::size_t m) const { return wheel_rad_s_[m]; }
    [[nodiscard]] plant::BodyVelocity body_velocity() const;

  private:
    plant::DiffDriveParams params_;
    std::array<double, 2> wheel_rad_s_{};
    plant::Pose pose_{};
    double t_s_ = 0.0;
};

}  // namespace ddmr::hostsim
