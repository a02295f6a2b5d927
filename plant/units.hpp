#pragma once
// Named constants and unit conversions used across plant/ (SI inside).

namespace ddmr::plant {

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kSecondsPerHour = 3600.0;

/// [rad/s] -> [rev/min]
inline constexpr double rad_s_to_rpm(double w) { return w * 60.0 / (2.0 * kPi); }
/// [rev/min] -> [rad/s]
inline constexpr double rpm_to_rad_s(double rpm) { return rpm * 2.0 * kPi / 60.0; }

}  // namespace ddmr::plant
