#pragma once
// The fidelity switches: each names one way in which the firmware, as it runs
// on the robot, differs from the thesis's idealised closed loop (ch. 5). The
// ideal model has none on; the firmware model has all on; any subset can be
// turned on to measure what one difference does on its own.
//
//   int_gains            `const int kx=1.1;` compiles to kx = 1: the gains are
//                        truncated to integers. With the firmware's values
//                        (1.1, 6, 8) only kx changes.
//   float32              the control law, the goal, the firmware's clock and
//                        the odometry in float (avr-gcc's double is 32-bit)
//                        instead of double.
//   encoder_odometry     the controller's pose is the sketch's dead reckoning
//                        from the edge counts (no direction), not the true pose.
//   loop_period          the control runs once per --period-ms (zero compute
//                        delay, the new PWM applied at once) instead of every
//                        plant step; its clock advances 0.01 s per iteration.
//   feedforward_constants eq. (17) with the sketch's constants: wheel speeds
//                        30.3 v +- 1.92 w, Ka = 0.0054, GR = 48, battery
//                        1/0.164 V fixed, instead of the inverse of eq. (6) and
//                        K_a, GR of the plant and the battery's measured voltage.
//   pwm_quantisation     int() of the 255-scale value, the sketch's clamping and
//                        direction logic, analogWrite of a negative value
//                        (pin 10: output low; pin 11: value & 0xFF), duty =
//                        value / 255; instead of duty = |V| / V_batt in [0, 1].
//   eeprom_bytes         the logged pose as the sketch writes it: int(E * 250)
//                        in one byte, every 10 iterations, case 1 only; instead
//                        of the unquantised pose every 0.1 s for every case.
//
// Each switch's exact semantics are in host_sim.hpp and docs/hostsim.md.

#include <array>
#include <bitset>
#include <cstddef>
#include <string>
#include <vector>

namespace ddmr::hostsim {

enum class FidelitySwitch {
    int_gains,
    float32,
    encoder_odometry,
    loop_period,
    feedforward_constants,
    pwm_quantisation,
    eeprom_bytes,
};

inline constexpr std::size_t kFidelitySwitchCount = 7;

/// Every switch's name, in the order of FidelitySwitch.
const std::array<const char*, kFidelitySwitchCount>& fidelity_switch_names();

const char* to_string(FidelitySwitch s);

/// A set of switches.
class Fidelity {
  public:
    /// The ideal model: no switch on.
    static Fidelity none() { return Fidelity{}; }
    /// The firmware model: every switch on.
    static Fidelity all();
    /// "a,b,c" (names from fidelity_switch_names(), any order, repeats
    /// allowed), or "none" / "" for none, or "all". Throws
    /// std::invalid_argument naming the unknown or empty element and listing
    /// the known names.
    static Fidelity parse(const std::string& list);

    Fidelity& set(FidelitySwitch s, bool on = true) {
        bits_.set(index(s), on);
        return *this;
    }
    [[nodiscard]] bool has(FidelitySwitch s) const { return bits_.test(index(s)); }
    [[nodiscard]] bool is_none() const { return bits_.none(); }
    [[nodiscard]] bool is_all() const { return bits_.all(); }
    /// The names of the switches that are on, in canonical order.
    [[nodiscard]] std::vector<std::string> names() const;
    /// names() joined by commas, or "none".
    [[nodiscard]] std::string to_string() const;

    friend bool operator==(const Fidelity& a, const Fidelity& b) { return a.bits_ == b.bits_; }
    friend bool operator!=(const Fidelity& a, const Fidelity& b) { return !(a == b); }

  private:
    static std::size_t index(FidelitySwitch s) { return static_cast<std::size_t>(s); }
    std::bitset<kFidelitySwitchCount> bits_;
};

}  // namespace ddmr::hostsim
