#pragma once
// One AVR timer's registers read from the data space at once (TCCRnA/B,
// OCRnx, ICRn, TCNTn; 16-bit ones as the chip holds them), for the parts that
// decode a timer: PinWaveforms (its output-compare pins) and PhaseCorrectTimer
// (its flags where simavr lacks the mode).

#include "hil/avr_core.hpp"
#include "hil/avr_timers.hpp"
#include "hil/timer_output.hpp"

namespace ddmr::hil {

/// The registers of timer `d` now (0 for those the timer lacks).
TimerRegisters read_timer_registers(const AvrCore& core, const TimerDesc& d);

/// The settings match: mode, clock, compare values and ICR (TCNT is not a
/// setting: it moves on its own).
bool same_settings(const TimerRegisters& a, const TimerRegisters& b);

}  // namespace ddmr::hil
