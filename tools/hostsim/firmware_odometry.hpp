#pragma once
// The sketch's dead reckoning from the encoder edge counts, line by line,
// templated on the number type (float: as on the robot).
//
//   phi1=Count1;  phi1dot=(phi1-phi1old)*radpuls*Gd;  phi1old=phi1;   (and 2)
//   Vel=0.5*r1*(phi1dot+phi2dot);
//   Omega=R*r1*(phi1dot-phi2dot);
//   Theta=Theta+dt*Omega;
//   Ex=Ex + dt*cos(Theta)*Vel;          (the new Theta: Euler, heading first)
//   Ey=Ey + dt*sin(Theta)*Vel;
//
// The counts have no direction (the Hall sensors' CHANGE interrupt only
// increments), so a wheel turning backwards is dead-reckoned as forwards.
// Gd = 1/dt = 100 and dt = 0.01 s are the sketch's constants, not the real
// period: since dt Gd = 1, the pose moves by the counted edges whatever the
// period (only phi1dot, Vel and Omega are wrong when the period is not 10 ms),
// so calling update() every plant step gives the same dead reckoning as
// calling it every 10 ms, up to when the counts are read.
// Constants: radpuls = 0.016362 rad per edge, r1 = 0.03215 m, R = 7.874 1/m.

#include <cstdint>

#include "tools/hostsim/kanayama.hpp"

namespace ddmr::hostsim {

template <class Real>
class FirmwareOdometry {
  public:
    FirmwareOdometry();

    /// One pass of the lines above with the counts read now; returns the pose.
    PoseEstimate<Real> update(std::uint64_t count1, std::uint64_t count2);

    [[nodiscard]] const PoseEstimate<Real>& pose() const { return pose_; }
    [[nodiscard]] Real wheel1_rad_s() const { return phi1dot_; }  ///< phi1dot [rad/s] (assumes dt)
    [[nodiscard]] Real wheel2_rad_s() const { return phi2dot_; }
    [[nodiscard]] Real velocity_m_s() const { return vel_; }      ///< Vel
    [[nodiscard]] Real omega_rad_s() const { return omega_; }     ///< Omega

  private:
    // the sketch's constants, as Real
    Real radpuls_;  ///< [rad/edge]
    Real dt_;       ///< [s]
    Real gd_;       ///< 1/dt [1/s], `(float)1.0/dt`
    Real r1_;       ///< [m]
    Real big_r_;    ///< 1/(2L) [1/m]
    // state
    std::int64_t phi1old_ = 0;  ///< counts at the previous update
    std::int64_t phi2old_ = 0;
    Real phi1dot_{};
    Real phi2dot_{};
    Real vel_{};
    Real omega_{};
    PoseEstimate<Real> pose_{};
};

extern template class FirmwareOdometry<float>;
extern template class FirmwareOdometry<double>;

}  // namespace ddmr::hostsim
