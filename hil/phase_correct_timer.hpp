#pragma once
// PhaseCorrectTimer: runs one AVR timer in the phase-correct PWM modes that
// simavr 1.6 lacks, with the datasheet's timing.
//
// The gap in simavr 1.6: its mode tables (cores/sim_megax8.h,
// sim_mega2560.h) have no entry for the phase-correct modes. These are
// Timer0/2 WGM 1 and 5, and Timer1/3/4/5 WGM 1, 2, 3, 10 and 11. In them
// simavr takes TOP as 0:
//   - a running timer raises TOVn every N cycles (N = the prescaler);
//   - it raises OCFnx only while OCRnx = 0;
//   - TCNTn reads (cycle - base) / N.
// Arduino's init() leaves Timer1 and Timer2 in WGM 1 at clk/64. Every sketch
// therefore ran with an overflow callback every 64 cycles, about 3,100 per
// 100,000 cycles (SIMAVR_NOTES.md).
//
// What this part does instead. While the timer is in such a mode, clocked
// from the prescaler (not T0/T1, not Timer2's asynchronous clock), it takes
// the timer over:
//   - It cancels simavr's cycle timers for it after each register access
//     simavr handles. These are the ones whose parameter is simavr's
//     avr_timer_t (overflow, compare A/B/C); an OCR write re-arms them in
//     these modes.
//   - It raises the flags at the datasheet's cycles (ATmega328P 7810D
//     §15.9.4, §17.7.4; DRIVERS.md §5). One period is 2·TOP·N cycles
//     (32,640 at TOP 255, clk/64):
//       TOVn   each time the count reaches BOTTOM;
//       OCFnx  each time the count reaches OCRnx in effect, counting up and
//              down (once a period if OCR is 0 or TOP, never if OCR > TOP);
//       ICF1   at TOP when ICR1 is TOP (mode 10). With OCR1A as TOP (mode
//              11), OCF1A's match at TOP is that flag.
//     avr_raise_interrupt sets each flag and pends its interrupt if it is
//     enabled, as simavr's own timers do. TIFRn's write-one-to-clear stays
//     simavr's.
//   - TCNTn reads as the 0..TOP..0 triangle.
// The counting and OCR double-buffering (updated at TOP) come from
// TimerOutputDecoder (hil/timer_output.hpp), the model the PWM pins use, so a
// flag and its pin's edge fall on the same cycle (until a TCNTn write, which
// PinWaveforms does not follow). Not modelled: input capture in these modes
// (simavr's ICP handler still runs, on its stale count) and TCNTn reads while
// the timer is stopped (simavr's: 0). A flag is set on the cycle
// the count reaches the value. In every other mode simavr runs the timer as
// before. Phase and frequency correct modes (Timer1 WGM 8, 9) are in simavr's
// table, with single-slope timing: not taken over.
//
// Signals:
//   in  TCCRnA, TCCRnB, OCRnx and ICRn through AvrCore::watch_io, after
//       simavr's own write handler. For 16-bit registers only the low byte:
//       the chip's TEMP register makes the low-byte write the one that counts.
//       TCNTn's read and write handlers are replaced by this part's; they
//       chain to simavr's.
//   out the timer's interrupt flags and vectors; TCNTn on each read.
// Fast-forward: its cycle timer replays after a jump while none of the
// timer's interrupts is enabled and the loop reads neither TCNTn nor TIFRn,
// as simavr's own flag-only timers do.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/avr_timers.hpp"
#include "hil/cycle_time.hpp"
#include "hil/timer_output.hpp"

struct avr_t;
struct avr_irq_t;
struct avr_timer_t;

namespace ddmr::hil {

struct LoopSpan;

class PhaseCorrectTimer {
public:
    /// Watches timer `desc` of the core's MCU (one of mcu().timers). Throws
    /// std::runtime_error if simavr has no such timer.
    PhaseCorrectTimer(AvrCore& core, const TimerDesc& desc);
    ~PhaseCorrectTimer();
    PhaseCorrectTimer(const PhaseCorrectTimer&) = delete;
    PhaseCorrectTimer& operator=(const PhaseCorrectTimer&) = delete;

    /// The timer is in a mode simavr lacks and runs from the prescaler:
    /// this part runs it.
    [[nodiscard]] bool active() const { return active_; }
    /// Whether simavr 1.6 lacks WGM `wgm` of this timer and the datasheet
    /// makes it phase-correct PWM.
    [[nodiscard]] bool takes_over(uint8_t wgm) const;

private:
    using IoRead = uint8_t (*)(avr_t*, uint16_t, void*);
    using IoWrite = void (*)(avr_t*, uint16_t, uint8_t, void*);

    static void on_register(avr_irq_t* irq, uint32_t value, void* param);
    static uint8_t on_tcnt_read(avr_t* avr, uint16_t address, void* param);
    static void on_tcnt_write(avr_t* avr, uint16_t address, uint8_t value, void* param);
    static uint64_t on_event(avr_t* avr, uint64_t when, void* param);

    void sample(bool tcnt_written);
    void take_or_leave(Cycles now);
    void cancel_simavr_timers();
    void reschedule(Cycles now);
    void raise_due(Cycles when);
    [[nodiscard]] Cycles next_event_after(Cycles cycle) const;
    [[nodiscard]] bool clocked_externally() const;
    [[nodiscard]] bool should_take_over() const;
    [[nodiscard]] bool any_interrupt_enabled() const;
    [[nodiscard]] bool may_replay(const LoopSpan& span) const;
    void reset();

    AvrCore& core_;
    TimerDesc desc_;
    avr_timer_t* sim_ = nullptr;  ///< simavr's module: its vectors, mode table and clock flags
    TimerOutputDecoder decoder_;
    TimerRegisters last_{};
    bool active_ = false;
    uint16_t watched_[7] = {};  ///< the registers watched (0: none)
    IoRead simavr_read_ = nullptr;
    void* simavr_read_param_ = nullptr;
    IoWrite simavr_write_ = nullptr;
    void* simavr_write_param_ = nullptr;
};

/// One PhaseCorrectTimer per timer of the core's MCU.
class PhaseCorrectTimers {
public:
    explicit PhaseCorrectTimers(AvrCore& core);
    [[nodiscard]] const PhaseCorrectTimer& timer(std::size_t n) const { return *timers_.at(n); }
    [[nodiscard]] std::size_t size() const { return timers_.size(); }

private:
    std::vector<std::unique_ptr<PhaseCorrectTimer>> timers_;
};

}  // namespace ddmr::hil
