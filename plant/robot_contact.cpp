// Robot and the world's walls: the body stops at a wall, and its wheels stall
// or slip there (body_contact.hpp, docs/world.md "Body and contact").
#include <cmath>

#include "plant/robot.hpp"

namespace ddmr::plant {

void Robot::set_world(const World* world) {
    world_ = world;
    contact_log_.reserve(kContactLog);
}

void Robot::resolve_contact(const RobotState& before) {
    if (const std::optional<WallContact> hit = body_contact(*world_, params_.body, state_.pose)) {
        // The step would have put a wall inside the body: it stays where it was.
        state_.pose = before.pose;
        state_.heading = before.heading;
        if (!contact_) {
            ++contact_count_;
            if (contact_log_.size() < kContactLog) {
                const BodyVelocity v = plant::body_velocity(
                    params_.kinematics, before.motor[0].speed_rad_s / params_.motor[0].gear_ratio,
                    before.motor[1].speed_rad_s / params_.motor[1].gear_ratio);
                contact_log_.push_back({before.t_s, hit->point_m.x(), hit->point_m.y(), std::fabs(v.v_m_s), hit->wall});
            }
        }
        contact_ = hit;
        if (params_.body.slip_at_contact == 0) contact_held_ = {true, true};
        return;
    }
    if (contact_held_[0] || contact_held_[1]) {
        // Stalled against the wall: the motors' torques (their currents) say
        // where the drive pushes the body; pulling it off frees the wheels.
        const BodyVelocity push =
            plant::body_velocity(params_.kinematics, state_.motor[0].current_A, state_.motor[1].current_A);
        if (!moves_off(*contact_, state_.pose, push)) return;
        contact_held_ = {false, false};
    }
    contact_.reset();
}

}  // namespace ddmr::plant
