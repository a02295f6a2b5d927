#pragma once
// From the control law's (v, w) to what each L298 bridge gets: wheel speeds by
// the inverse of eq. (6), motor voltages by eq. (17), then a duty and a
// direction, either continuous (the thesis's idealisation) or as the sketch's
// int arithmetic and analogWrite produce them.
//
//   inverse eq. (6):  phi_1 = (v + L w) / r_1   (motor 1, RIGHT wheel)
//                     phi_2 = (v - L w) / r_2   (motor 2, LEFT wheel)
//   the sketch:       phi_1 = 30.3 v + 1.92 w,  phi_2 = 30.3 v - 1.92 w
//   eq. (17):         V = GR K_a phi
//   255-scale value:  u = 255 V / V_batt   (the sketch: 255.0*GR*Ka*(...)*Batt)
//
// Continuous (pwm_quantisation off): duty = min(|u| / 255, 1), i.e. V clamped
// to the battery; direction forward for u > 0, reverse for u < 0, unchanged
// for u = 0.
//
// Quantised (pwm_quantisation on), the sketch line by line:
//   Vdc = int(u)                            truncation toward zero
//   if (Vdc>0)   DIR = HIGH                 forward
//   if (Vdc>255) Vdc = 255
//   if (Vdc<0)   DIR = LOW                  reverse (Vdc = 0: DIR unchanged)
//   analogWrite(EN, Vdc):
//     0 -> pin LOW, 255 -> pin HIGH, 1..254 -> OCR = Vdc, duty Vdc / 255;
//     negative, pin 10 (motor 1, Timer1, 16-bit OCR1B): -30 is stored as
//       65506, above the 8-bit count's TOP, never matched: the pin stays LOW
//       (duty 0; hil/motor_driver_reader.hpp decodes the same);
//     negative, pin 11 (motor 2, Timer2, 8-bit OCR2A): the low byte,
//       -30 -> 226, duty 226 / 255 = 88.6 % in reverse.
// The sketch never clamps below -255, so -256 .. -32768 wrap too.

#include <cstddef>
#include <cstdint>

#include "plant/diff_drive_kinematics.hpp"
#include "tools/hostsim/firmware_constants.hpp"
#include "tools/hostsim/kanayama.hpp"

namespace ddmr::hostsim {

/// Desired wheel speeds [rad/s at the wheel].
template <class Real>
struct WheelSpeeds {
    Real right_rad_s;  ///< phi_1, motor 1
    Real left_rad_s;   ///< phi_2, motor 2
};

/// Inverse of eq. (6) with the plant's geometry.
template <class Real>
WheelSpeeds<Real> inverse_kinematics(const plant::DiffDriveParams& p, const VelocityCommand<Real>& c) {
    const Real half_axle = static_cast<Real>(p.half_axle_m);
    return {(c.v_m_s + half_axle * c.omega_rad_s) / static_cast<Real>(p.wheel_radius_right_m),
            (c.v_m_s - half_axle * c.omega_rad_s) / static_cast<Real>(p.wheel_radius_left_m)};
}

/// The sketch's inverse: `30.3*v+1.92*w`, `30.3*v-1.92*w`.
template <class Real>
WheelSpeeds<Real> firmware_wheel_speeds(const VelocityCommand<Real>& c) {
    const Real a = static_cast<Real>(firmware::kSpeedToWheel_per_m);
    const Real b = static_cast<Real>(firmware::kTurnToWheel);
    return {a * c.v_m_s + b * c.omega_rad_s, a * c.v_m_s - b * c.omega_rad_s};
}

/// eq. (17) on the 255 scale, in the sketch's order:
/// ((255 GR) K_a) phi / V_batt  (the sketch multiplies by Batt = 1 / V_batt).
template <class Real>
Real drive_value_255(Real gear_ratio, Real ka_V_s_per_rad, Real wheel_rad_s, Real inverse_battery_per_V) {
    return static_cast<Real>(firmware::kPwmFullScale) * gear_ratio * ka_V_s_per_rad * wheel_rad_s *
           inverse_battery_per_V;
}

/// Which timer drives the bridge's enable pin: what analogWrite does with a
/// negative value depends on it.
enum class PwmTimer {
    timer1_ocr1b,  ///< pin 10, motor 1: 16-bit OCR, a negative value keeps the pin low
    timer2_ocr2a,  ///< pin 11, motor 2: 8-bit OCR, a negative value wraps to its low byte
};

/// The sketch's wiring: motor 1 on pin 10, motor 2 on pin 11.
inline constexpr PwmTimer pwm_timer_of_motor(std::size_t m) {
    return m == 0 ? PwmTimer::timer1_ocr1b : PwmTimer::timer2_ocr2a;
}

/// What one bridge gets.
struct BridgeCommand {
    double duty = 0.0;        ///< mean enable level, [0, 1]
    bool forward = true;      ///< direction pin
    std::uint8_t ocr = 0;     ///< the PWM compare value for the switched waveform (0 low, 255 high)
    int value = 0;            ///< quantised: the clamped Vdc passed to analogWrite; continuous: 0
};

/// `int(u)` as the AVR computes it for |u| < 32768 (truncation toward zero);
/// beyond, or NaN, saturated to the 16-bit range (the robot would wrap; no
/// reachable command comes near: |v| would exceed 90 m/s).
int firmware_int(double u);

/// Continuous drive from the 255-scale value u.
BridgeCommand continuous_drive(double u, bool previous_forward);

/// The sketch's clamping, direction and analogWrite for Vdc = int(u).
BridgeCommand quantised_drive(int vdc, PwmTimer timer, bool previous_forward);

}  // namespace ddmr::hostsim
