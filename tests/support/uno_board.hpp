#pragma once
// The Arduino Uno the reference firmware runs on in most tests: its clock,
// for the tests' conversions between cycles and seconds (the HIL takes it
// from AvrCore::clock_hz()).

#include <cstdint>

#include "hil/board_description.hpp"

namespace ddmr::test {

inline const hil::BoardDescription& uno() { return hil::board_description(hil::BoardModel::uno); }
/// The Uno's 16 MHz crystal [Hz].
inline constexpr uint32_t kUnoClockHz = 16'000'000;

}  // namespace ddmr::test
