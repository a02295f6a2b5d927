#include "tools/hostsim/firmware_odometry.hpp"

#include <cmath>

#include "tools/hostsim/firmware_constants.hpp"

namespace ddmr::hostsim {

template <class Real>
FirmwareOdometry<Real>::FirmwareOdometry()
    : radpuls_(static_cast<Real>(firmware::kRadPerEdge)),
      dt_(static_cast<Real>(firmware::kDt_s)),
      gd_(Real(1) / static_cast<Real>(firmware::kDt_s)),
      r1_(static_cast<Real>(firmware::kWheelRadius_m)),
      big_r_(static_cast<Real>(firmware::kInverseTrack_per_m)) {}

template <class Real>
PoseEstimate<Real> FirmwareOdometry<Real>::update(std::uint64_t count1, std::uint64_t count2) {
    // The sketch's counters are 32-bit (unsigned long -> signed long): no
    // wrap in any run shorter than years.
    const auto phi1 = static_cast<std::int64_t>(count1);
    const auto phi2 = static_cast<std::int64_t>(count2);
    phi1dot_ = static_cast<Real>(phi1 - phi1old_) * radpuls_ * gd_;
    phi2dot_ = static_cast<Real>(phi2 - phi2old_) * radpuls_ * gd_;
    phi1old_ = phi1;
    phi2old_ = phi2;
    vel_ = static_cast<Real>(0.5) * r1_ * (phi1dot_ + phi2dot_);
    omega_ = big_r_ * r1_ * (phi1dot_ - phi2dot_);
    pose_.theta_rad = pose_.theta_rad + dt_ * omega_;
    pose_.x_m = pose_.x_m + dt_ * std::cos(pose_.theta_rad) * vel_;
    pose_.y_m = pose_.y_m + dt_ * std::sin(pose_.theta_rad) * vel_;
    return pose_;
}

template class FirmwareOdometry<float>;
template class FirmwareOdometry<double>;

}  // namespace ddmr::hostsim
