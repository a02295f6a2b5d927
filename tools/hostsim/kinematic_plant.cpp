#include "tools/hostsim/kinematic_plant.hpp"

namespace ddmr::hostsim {

void KinematicPlant::step(double dt_s) {
    plant::advance_exact_arc(params_, pose_, wheel_rad_s_[0] * dt_s, wheel_rad_s_[1] * dt_s);
    t_s_ += dt_s;
}

plant::BodyVelocity KinematicPlant::body_velocity() const {
    return plant::body_velocity(params_, wheel_rad_s_[0], wheel_rad_s_[1]);
}

}  // namespace ddmr::hostsim
