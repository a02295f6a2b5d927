#pragma once
// The Uno's analogWrite() waveform on pins 10 (Timer1, OC1B) and 11 (Timer2,
// OC2A): 8-bit phase-correct PWM, prescaler 64, 16 MHz clock.
//
//   counter: 0, 1, ..., 255, 254, ..., 1, 0, ...  one count per 64 cycles
//   period : 2 x 255 x 64 = 32640 cycles = 2.04 ms (490.196 Hz)
//   output : high while the counter is below OCR (non-inverting), i.e. for
//            2 x OCR x 64 cycles per period, centred on the counter's BOTTOM.
//            OCR = 0: always low; OCR = 255: always high (as analogWrite does).
//
// Time is counted in AVR cycles; convert with cycles_to_s / s_to_cycles.
// Header only: the HIL reuses these timing facts.

#include <cmath>
#include <cstdint>
#include <limits>

namespace ddmr::plant {

inline constexpr std::int64_t kCpuHz = 16'000'000;  ///< ATmega328P clock on the Uno

inline constexpr double cycles_to_s(std::int64_t cycles) {
    return static_cast<double>(cycles) / static_cast<double>(kCpuHz);
}
/// Seconds to the nearest whole cycle.
inline std::int64_t s_to_cycles(double seconds) {
    return static_cast<std::int64_t>(std::llround(seconds * static_cast<double>(kCpuHz)));
}

struct PhaseCorrectPwm {
    static constexpr std::int64_t kPrescaler = 64;
    static constexpr std::int64_t kTop = 255;
    static constexpr std::int64_t kPeriodCycles = 2 * kTop * kPrescaler;  ///< 32640
    static constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();

    std::uint8_t ocr = 0;             ///< compare value, what analogWrite() stores
    std::int64_t bottom_cycle = 0;    ///< a cycle at which the counter is at BOTTOM

    /// OCR that analogWrite(round(duty x 255)) sets; duty is clamped to [0, 1].
    static std::uint8_t ocr_for_duty(double duty) {
        const double d = duty < 0.0 ? 0.0 : (duty > 1.0 ? 1.0 : duty);
        return static_cast<std::uint8_t>(std::lround(d * 255.0));
    }
    /// High cycles per period: 2 x OCR x 64.
    [[nodiscard]] constexpr std::int64_t on_cycles() const { return std::int64_t{2} * ocr * kPrescaler; }
    /// Fraction of the period spent high: OCR / 255.
    [[nodiscard]] constexpr double duty() const { return static_cast<double>(ocr) / 255.0; }

    /// Position in the period, [0, kPeriodCycles), 0 at BOTTOM.
    [[nodiscard]] constexpr std::int64_t phase(std::int64_t cycle) const {
        const std::int64_t p = (cycle - bottom_cycle) % kPeriodCycles;
        return p < 0 ? p + kPeriodCycles : p;
    }
    /// Pin level during cycle `cycle`.
    [[nodiscard]] constexpr bool level_at(std::int64_t cycle) const {
        const std::int64_t p = phase(cycle);
        const std::int64_t half_on = on_cycles() / 2;
        return p < half_on || p >= kPeriodCycles - half_on;
    }
    /// First cycle after `cycle` at which the level changes; kNever if constant.
    [[nodiscard]] constexpr std::int64_t next_edge_after(std::int64_t cycle) const {
        if (ocr == 0 || ocr == kTop) return kNever;
        const std::int64_t p = phase(cycle);
        const std::int64_t half_on = on_cycles() / 2;
        if (p < half_on) return cycle + (half_on - p);                                  // falling
        if (p < kPeriodCycles - half_on) return cycle + (kPeriodCycles - half_on - p);  // rising
        return cycle + (kPeriodCycles - p) + half_on;                                  // falling
    }
};

}  // namespace ddmr::plant
