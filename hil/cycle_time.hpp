#pragma once
// AVR time is counted in clock cycles (uint64_t, as simavr's avr_cycle_count_t).
// These are the only conversions between cycles and SI time in the project;
// the clock is always the board's (AvrCore::clock_hz(), BoardDescription::clock_hz).

#include <cmath>
#include <cstdint>

namespace ddmr::hil {

using Cycles = uint64_t;

/// Seconds of simulated time covered by `cycles` at `clock_hz`.
constexpr double cycles_to_s(Cycles cycles, uint32_t clock_hz) {
    return static_cast<double>(cycles) / static_cast<double>(clock_hz);
}

/// Cycles in `seconds` (rounded to the nearest cycle). `seconds` must be >= 0.
inline Cycles s_to_cycles(double seconds, uint32_t clock_hz) {
    return static_cast<Cycles>(std::llround(seconds * static_cast<double>(clock_hz)));
}

/// Cycles in `ms` milliseconds.
inline Cycles ms_to_cycles(double ms, uint32_t clock_hz) {
    return s_to_cycles(ms * 1e-3, clock_hz);
}

}  // namespace ddmr::hil
