#pragma once
// The HC-SR04 ultrasonic ranger's echo, from its datasheet and the PING)))
// sheet it follows (../shared/SENSORS.md section 1):
//   - the module sends 8 cycles at 40 kHz (200 us, [PING] p. 2 tBURST) after
//     a TRIG pulse of at least 10 us ([SR04] p. 1) and raises ECHO;
//   - ECHO stays high for the sound's round trip, 2 d / c ([SR04] p. 2:
//     "high level time x velocity of sound (340 m/s) / 2");
//   - c = 331.5 + 0.6 T m/s, T in degrees Celsius ([PING] p. 3);
//   - the range is 2 cm to 4 m and the beam 15 degrees wide ([SR04] p. 1);
//   - with no echo the module lowers ECHO after about 38 ms (module-specific:
//     [HCV], [SRF04] "about 36 ms").
// Pure functions of plain parameters; SI units.

#include <optional>

#include "plant/units.hpp"
#include "plant/world.hpp"

namespace ddmr::plant {

struct SonarParams {
    double cone_full_angle_rad = 15.0 * kPi / 180.0;  ///< [SR04] "measuring angle 15"
    /// A wall struck more obliquely than this (between the ray and the wall's
    /// normal) reflects the burst away from the receiver: no echo. Not in the
    /// datasheet ("targets should be smooth and >= 0.5 m^2"): a model choice.
    double max_incidence_rad = 45.0 * kPi / 180.0;
    double min_range_m = 0.02;   ///< a nearer wall reads as this
    double max_range_m = 4.0;    ///< farther: no echo
    double temperature_c = 20.0;
    double burst_s = 200e-6;       ///< TRIG's falling edge to ECHO's rise
    double no_echo_s = 38e-3;      ///< ECHO's width with no echo
    double mount_height_m = 0.05;  ///< the beam's height: lower walls are not seen
};

/// The speed of sound [m/s] at `temperature_c` ([PING] p. 3).
double speed_of_sound_m_s(double temperature_c);

/// What one ping measures: the distance to the nearest wall inside the cone
/// (clamped up to min_range_m), or none (no wall in range, or only ones
/// struck beyond max_incidence_rad).
std::optional<double> sonar_distance_m(const World& world, const SonarParams& p, const Eigen::Vector2d& origin_m,
                                       double direction_rad);

/// ECHO's high time [s]: 2 d / c for a distance, no_echo_s for none.
double echo_width_s(const SonarParams& p, std::optional<double> distance_m);

}  // namespace ddmr::plant
