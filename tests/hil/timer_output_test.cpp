// TimerOutputDecoder: every output-compare waveform of the ATmega328P's
// Timer0/1/2, checked against values worked out by hand from the datasheet
// (7810D ch. 14, 15, 17) and, for the 8-bit phase-correct PWM the Uno's
// analogWrite uses on Timer1/Timer2, bit for bit against the decoding the HIL
// used before (motor_driver_reader.cpp + plant/pwm_waveform.hpp).
#include "hil/timer_output.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>

#include "hil/avr_timers.hpp"
#include "hil/mcu.hpp"
#include "plant/pwm_waveform.hpp"

namespace ddmr::test {
namespace {

using hil::Cycles;
using hil::TimerOutputDecoder;
using hil::TimerRegisters;
constexpr Cycles kNever = TimerOutputDecoder::kNever;
constexpr int kA = 0;
constexpr int kB = 1;

// Clock-select codes (CSn2:0).
constexpr unsigned kCs1 = 1;    // N = 1 on every timer
constexpr unsigned kCs8 = 2;    // N = 8 on every timer
constexpr unsigned kCs64 = 3;   // Timer0/1: N = 64 (Timer2: 32)
constexpr unsigned kCs2By64 = 4;  // Timer2: N = 64 (Table 17-9)

/// One timer and the register file the firmware writes.
struct Timer {
    explicit Timer(int n, const hil::TimerOutputOptions& options = {})
        : dec(hil::kAtmega328pTimers[static_cast<std::size_t>(n)], options) {}

    /// WGM, clock select and COMnA/COMnB as TCCRnA/TCCRnB hold them.
    void mode(unsigned wgm, unsigned cs, unsigned com_a, unsigned com_b) {
        regs.tccra = static_cast<uint8_t>((com_a << 6U) | (com_b << 4U) | (wgm & 3U));
        regs.tccrb = static_cast<uint8_t>(((wgm >> 2U) << 3U) | cs);
    }
    bool write(Cycles cycle) { return dec.on_write(cycle, regs, false); }
    /// Mode and OCRs written while stopped (they take effect at once), then the
    /// clock started: the counter is at BOTTOM at `cycle`.
    void start(unsigned wgm, unsigned cs, unsigned com_a, unsigned com_b, Cycles cycle = 0) {
        mode(wgm, 0, com_a, com_b);
        write(cycle);
        mode(wgm, cs, com_a, com_b);
        write(cycle);
    }
    bool write_tcnt(Cycles cycle, uint16_t value) {
        regs.tcnt = value;
        return dec.on_write(cycle, regs, true);
    }

    TimerRegisters regs;
    TimerOutputDecoder dec;
};

/// A periodic waveform read back by walking its edges.
struct Measured {
    Cycles period = 0;  ///< [cycles] between rising edges (all equal, else 0)
    Cycles high = 0;    ///< [cycles] high per period (all equal, else 0)
};

/// Walks `periods` periods from the first rising edge after `from`, checking
/// that the level is constant between the reported edges and flips at each.
Measured measure(const TimerOutputDecoder& d, int ch, Cycles from, int periods = 4) {
    Cycles t = d.next_change_after(ch, from);
    if (t != kNever && !d.level_at(ch, t)) t = d.next_change_after(ch, t);
    if (t == kNever) return {};
    Measured m{kNever, kNever};
    Cycles rise = t;
    Cycles high = 0;
    for (int k = 0; k < periods;) {
        const Cycles next = d.next_change_after(ch, t);
        EXPECT_NE(next, kNever);
        EXPECT_EQ(d.level_at(ch, next - 1), d.level_at(ch, t)) << "at " << next - 1;
        EXPECT_NE(d.level_at(ch, next), d.level_at(ch, t)) << "at " << next;
        if (d.level_at(ch, t)) high += next - t;
        t = next;
        if (!d.level_at(ch, t)) continue;
        const Cycles period = t - rise;
        m.period = m.period == kNever || m.period == period ? period : 0;
        m.high = m.high == kNever || m.high == high ? high : 0;
        rise = t;
        high = 0;
        ++k;
    }
    return m;
}

double hz(Cycles period) { return 16e6 / static_cast<double>(period); }

// ---- the timers as data ------------------------------------------------------------

TEST(AvrTimers, RegisterSummaryAndPrescalers) {
    const auto& t = hil::kAtmega328pTimers;
    EXPECT_EQ(t[0].tccra, 0x44);
    EXPECT_EQ(t[0].ocrb_low, 0x48);
    EXPECT_EQ(t[1].icr_low, 0x86);
    EXPECT_EQ(t[1].ocrb_high, 0x8B);
    EXPECT_EQ(t[2].ocra_low, 0xB3);
    EXPECT_EQ(t[2].ocra_high, 0);  // 8-bit: absent
    EXPECT_EQ(t[0].prescaler[3], 64);
    EXPECT_EQ(t[0].prescaler[6], 0);  // external clock: treated as stopped
    EXPECT_EQ(t[2].prescaler[3], 32);
    EXPECT_EQ(t[2].prescaler[4], 64);
    EXPECT_EQ(t[1].max(), 0xFFFFu);
    EXPECT_EQ(t[1].modes[14].top_source, hil::TopSource::kIcr);
    EXPECT_EQ(t[2].pins[1].port, 'D');  // OC2B = PD3 = Uno D3
    EXPECT_EQ(t[2].pins[1].bit, 3);
}

// ---- Arduino init()'s modes, all six channels ------------------------------------------

// Timer0, mode 3 (fast PWM, TOP 0xFF), N = 64: period 256 x 64 = 16384 cycles
// (976.5625 Hz); high while count <= OCR: OCR0A 100 -> 101 x 64 = 6464 cycles,
// OCR0B 200 -> 201 x 64 = 12864 cycles.
TEST(TimerOutputDecoder, ArduinoTimer0FastPwm) {
    Timer t(0);
    t.regs.ocra = 100;
    t.regs.ocrb = 200;
    t.start(3, kCs64, 2, 2);
    const Measured a = measure(t.dec, kA, 0);
    EXPECT_EQ(a.period, 16384u);
    EXPECT_DOUBLE_EQ(hz(a.period), 976.5625);
    EXPECT_EQ(a.high, 6464u);
    EXPECT_EQ(measure(t.dec, kB, 0).high, 12864u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 101.0 / 256.0);
    EXPECT_EQ(t.dec.period_cycles(kB), 16384u);
}

// Timer1 mode 1 and Timer2 mode 1 (phase correct, TOP 0xFF), N = 64: period
// 2 x 255 x 64 = 32640 cycles (490.196 Hz); high 2 x OCR x 64: OCR 100 -> 12800,
// OCR 200 -> 25600.
TEST(TimerOutputDecoder, ArduinoTimer1And2PhaseCorrect) {
    for (const int n : {1, 2}) {
        Timer t(n);
        t.regs.ocra = 100;
        t.regs.ocrb = 200;
        t.start(1, n == 1 ? kCs64 : kCs2By64, 2, 2);
        const Measured a = measure(t.dec, kA, 0);
        EXPECT_EQ(a.period, 32640u) << "timer " << n;
        EXPECT_NEAR(hz(a.period), 490.196, 1e-3);
        EXPECT_EQ(a.high, 12800u);
        EXPECT_EQ(measure(t.dec, kB, 0).high, 25600u);
        EXPECT_DOUBLE_EQ(t.dec.duty(kB), 200.0 / 255.0);
    }
}

// COM 11: the complement. Fast PWM OCR 100: high 16384 - 6464 = 9920; phase
// correct OCR 100: high 32640 - 12800 = 19840.
TEST(TimerOutputDecoder, InvertingModeOnAllSixChannels) {
    for (const int n : {0, 1, 2}) {
        Timer t(n);
        t.regs.ocra = 100;
        t.regs.ocrb = 100;
        t.start(n == 0 ? 3 : 1, n == 2 ? kCs2By64 : kCs64, 3, 3);
        const Cycles high = n == 0 ? 9920 : 19840;
        for (const int ch : {kA, kB}) {
            EXPECT_EQ(measure(t.dec, ch, 0).high, high) << "timer " << n << " channel " << ch;
            EXPECT_DOUBLE_EQ(t.dec.duty(ch), n == 0 ? 155.0 / 256.0 : 155.0 / 255.0);
        }
    }
}

// ---- Timer1's other PWM modes --------------------------------------------------------

// Mode 7 (fast PWM 10-bit, TOP 0x3FF), N = 1: period 1024 cycles (15.625 kHz);
// OCR1A 511 -> high 512 (50 %), OCR1B 100 -> high 101.
TEST(TimerOutputDecoder, Timer1FastPwm10Bit) {
    Timer t(1);
    t.regs.ocra = 511;
    t.regs.ocrb = 100;
    t.start(7, kCs1, 2, 2);
    EXPECT_EQ(measure(t.dec, kA, 0).period, 1024u);
    EXPECT_EQ(measure(t.dec, kA, 0).high, 512u);
    EXPECT_EQ(measure(t.dec, kB, 0).high, 101u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 0.5);
}

// Mode 14 (fast PWM, TOP = ICR1 = 799), N = 1: period 800 cycles = 20 kHz;
// OCR1A 199 -> high 200 (25 %), OCR1B 599 -> high 600. COM1A = 01 toggles OC1A
// on each OCR1A match (Table 15-3): period 1600, high 800.
TEST(TimerOutputDecoder, Timer1Mode14IcrTop20kHz) {
    Timer t(1);
    t.regs.icr = 799;
    t.regs.ocra = 199;
    t.regs.ocrb = 599;
    t.start(14, kCs1, 2, 2);
    const Measured a = measure(t.dec, kA, 0);
    EXPECT_EQ(a.period, 800u);
    EXPECT_DOUBLE_EQ(hz(a.period), 20000.0);
    EXPECT_EQ(a.high, 200u);
    EXPECT_EQ(measure(t.dec, kB, 0).high, 600u);
    t.mode(14, kCs1, 1, 2);
    t.write(5000);
    EXPECT_TRUE(t.dec.connected(kA));
    EXPECT_EQ(measure(t.dec, kA, 5000).period, 1600u);
    EXPECT_EQ(measure(t.dec, kA, 5000).high, 800u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 0.5);
}

// Mode 8 (phase and frequency correct, TOP = ICR1 = 1000), N = 8: period
// 2 x 1000 x 8 = 16000 cycles (1 kHz); OCR1A 250 -> high 2 x 250 x 8 = 4000,
// OCR1B 750 -> 12000.
TEST(TimerOutputDecoder, Timer1PhaseFrequencyCorrectMode8) {
    Timer t(1);
    t.regs.icr = 1000;
    t.regs.ocra = 250;
    t.regs.ocrb = 750;
    t.start(8, kCs8, 2, 2);
    EXPECT_EQ(measure(t.dec, kA, 0).period, 16000u);
    EXPECT_EQ(measure(t.dec, kA, 0).high, 4000u);
    EXPECT_EQ(measure(t.dec, kB, 0).high, 12000u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 0.25);
    // PFC updates OCR at BOTTOM: a write at 100 takes effect at 16000.
    t.regs.ocra = 500;
    t.write(100);
    EXPECT_EQ(t.dec.pending_update_cycle(), 16000u);
}

// Mode 11 (phase correct, TOP = OCR1A, updated at TOP), N = 1, TOP 100, OCR1B 50.
// OCR1A = 200 written at 10 takes effect at TOP (cycle 100): the count runs down
// from the old TOP 100 (BOTTOM at 200), then up to 200 and down (BOTTOM at 600):
// the asymmetric period the datasheet warns of (§15.9.4). OC1B rises on the
// down-count match at 50 (cycle 150), falls at count 50 going up (250), rises
// at 600 - 50 = 550.
TEST(TimerOutputDecoder, Timer1PhaseCorrectTopChangeIsAsymmetric) {
    Timer t(1);
    t.regs.ocra = 100;
    t.regs.ocrb = 50;
    t.start(11, kCs1, 0, 2);
    t.regs.ocra = 200;
    t.write(10);
    EXPECT_EQ(t.dec.pending_update_cycle(), 100u);
    EXPECT_EQ(t.dec.advance_to(100), std::optional<Cycles>(100));
    EXPECT_EQ(t.dec.next_change_after(kB, 100), 150u);
    EXPECT_EQ(t.dec.next_change_after(kB, 150), 250u);
    EXPECT_EQ(t.dec.next_change_after(kB, 250), 550u);
    EXPECT_EQ(t.dec.period_cycles(kB), 400u);  // 2 x 200 x 1 from now on
}

// ---- toggling --------------------------------------------------------------------------

// Timer2 CTC (mode 2), TOP = OCR2A = 249, N = 64: a match every 250 x 64 =
// 16000 cycles; COM2A = 01 toggles OC2A: period 32000 cycles = 500 Hz, high
// 16000. OC2B toggles too (OCR2B = 100 <= TOP), same period, shifted.
TEST(TimerOutputDecoder, Timer2CtcToggle500Hz) {
    Timer t(2);
    t.regs.ocra = 249;
    t.regs.ocrb = 100;
    t.start(2, kCs2By64, 1, 1);
    EXPECT_EQ(t.dec.pending_update_cycle(), kNever);  // CTC: OCR2A written at once
    const Measured a = measure(t.dec, kA, 0);
    EXPECT_EQ(a.period, 32000u);
    EXPECT_DOUBLE_EQ(hz(a.period), 500.0);
    EXPECT_EQ(a.high, 16000u);
    EXPECT_EQ(t.dec.next_change_after(kA, 0), 249u * 64u);   // first match: count 249
    EXPECT_EQ(t.dec.next_change_after(kB, 0), 100u * 64u);   // count 100
    EXPECT_EQ(measure(t.dec, kB, 0).period, 32000u);
    EXPECT_EQ(t.dec.period_cycles(kA), 32000u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kB), 0.5);
}

// Timer0 mode 7 (fast PWM, TOP = OCR0A = 99, buffered at BOTTOM), N = 8:
// counter period 100 x 8 = 800 cycles. COM0A = 01 toggles OC0A at each TOP
// match: period 1600 (10 kHz), high 800. OC0B (COM 10, OCR0B 49): high 50 x 8
// = 400 of 800. The mode is set with OCR0A = 0 (TOP 0: period 8 cycles); the
// OCR0A write at 3 takes effect at the next BOTTOM, cycle 8.
TEST(TimerOutputDecoder, Timer0Mode7OcrATopToggles) {
    Timer t(0);
    t.mode(7, kCs8, 1, 2);
    t.write(0);
    t.regs.ocra = 99;
    t.regs.ocrb = 49;
    t.write(3);
    EXPECT_EQ(t.dec.pending_update_cycle(), 8u);
    EXPECT_EQ(t.dec.advance_to(8), std::optional<Cycles>(8));
    EXPECT_EQ(measure(t.dec, kA, 8).period, 1600u);
    EXPECT_EQ(measure(t.dec, kA, 8).high, 800u);
    const Measured b = measure(t.dec, kB, 8);
    EXPECT_EQ(b.period, 800u);
    EXPECT_EQ(b.high, 400u);
}

// Normal mode (TOP 0xFF), N = 1, OCR0A = 10: a match at 10, 266, 522, ...
// COM 01 toggles (period 512); COM 11 sets at the next match and stays high;
// COM 10 then clears at the following match.
TEST(TimerOutputDecoder, NormalModeToggleSetClear) {
    Timer t(0);
    t.mode(0, kCs1, 1, 0);
    t.regs.ocra = 10;
    t.write(0);
    EXPECT_EQ(t.dec.next_change_after(kA, 0), 10u);
    EXPECT_EQ(measure(t.dec, kA, 0).period, 512u);
    EXPECT_FALSE(t.dec.level_at(kA, 9));
    EXPECT_TRUE(t.dec.level_at(kA, 10));
    t.mode(0, kCs1, 3, 0);  // set on match; OC0A is high now (toggled at 10)
    t.write(100);
    EXPECT_TRUE(t.dec.level_at(kA, 100));
    EXPECT_EQ(t.dec.next_change_after(kA, 100), kNever);
    t.mode(0, kCs1, 2, 0);  // clear on match: low from 266
    t.write(200);
    EXPECT_TRUE(t.dec.level_at(kA, 265));
    EXPECT_EQ(t.dec.next_change_after(kA, 200), 266u);
    EXPECT_FALSE(t.dec.level_at(kA, 5000));
    EXPECT_EQ(t.dec.next_change_after(kA, 266), kNever);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 0.0);
}

// ---- double buffering, TCNT writes, stops ------------------------------------------

// Timer1 mode 1, N = 64, started at 0: TOPs at 16320 + k x 32640. OCR1A 100 ->
// 50 written at 1000 takes effect at 16320: the rising edge on the way down
// moves from 32640 - 6400 = 26240 to 32640 - 3200 = 29440. A write exactly at a
// TOP (48960) waits for the next one (81600).
TEST(TimerOutputDecoder, PhaseCorrectOcrTakesEffectAtTheNextTop) {
    Timer t(1);
    t.regs.ocra = 100;
    t.start(1, kCs64, 2, 0);
    t.regs.ocra = 50;
    EXPECT_FALSE(t.write(1000));  // buffered: nothing changes yet
    EXPECT_EQ(t.dec.pending_update_cycle(), 16320u);
    EXPECT_EQ(t.dec.next_change_after(kA, 1000), 6400u);
    EXPECT_EQ(t.dec.advance_to(16319), std::nullopt);
    EXPECT_EQ(t.dec.advance_to(20000), std::optional<Cycles>(16320));
    EXPECT_EQ(t.dec.next_change_after(kA, 20000), 29440u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 50.0 / 255.0);
    t.regs.ocra = 60;
    t.write(48960);  // at a TOP: waits for the next one
    EXPECT_EQ(t.dec.pending_update_cycle(), 81600u);
}

// Fast PWM updates at BOTTOM: Timer0 mode 3, N = 64, OCR0A 10 -> 20 written at
// 1000 takes effect at 16384 (then high for 21 x 64 = 1344 cycles). CTC writes
// at once: OCR0A = 30 is TOP at once; COM 01 toggles, period 2 x 31 x 64.
TEST(TimerOutputDecoder, FastPwmOcrTakesEffectAtBottom) {
    Timer t(0);
    t.regs.ocra = 10;
    t.start(3, kCs64, 2, 0);
    t.regs.ocra = 20;
    t.write(1000);
    EXPECT_EQ(t.dec.pending_update_cycle(), 16384u);
    EXPECT_EQ(t.dec.next_change_after(kA, 1000), 16384u);  // fell at 11 x 64 = 704
    t.dec.advance_to(16384);
    EXPECT_EQ(t.dec.next_change_after(kA, 16384), 16384u + 21u * 64u);
    t.mode(2, kCs64, 1, 0);  // CTC: TOP = OCR0A at once
    t.regs.ocra = 30;
    EXPECT_TRUE(t.write(20000));
    EXPECT_EQ(t.dec.pending_update_cycle(), kNever);
    EXPECT_EQ(t.dec.period_cycles(kA), 2u * 31u * 64u);
}

// An update due before a later write is applied at its own TOP: OCR1A 100 ->
// 50 at 1000 (due 16320), then -> 80 at 20000 without advance_to in between:
// 50 rules from 16320 (rising at 29440), 80 from 48960.
TEST(TimerOutputDecoder, DueUpdateIsNotLostToALaterWrite) {
    Timer t(1);
    t.regs.ocra = 100;
    t.start(1, kCs64, 2, 0);
    t.regs.ocra = 50;
    t.write(1000);
    t.regs.ocra = 80;
    t.write(20000);
    EXPECT_EQ(t.dec.next_change_after(kA, 20000), 29440u);
    EXPECT_EQ(t.dec.pending_update_cycle(), 48960u);
    EXPECT_EQ(t.dec.advance_to(21000), std::optional<Cycles>(16320));
}

// TCNT0 = 128 written at 5000 (Timer0 mode 3, N = 64, OCR0A 100): the count is
// 128 (> OCR: low) and reaches BOTTOM at 5000 + 128 x 64 = 13192 (rising), then
// falls at 13192 + 101 x 64 = 19656. Writing TCNT while stopped: the count
// resumes from it when the clock starts.
TEST(TimerOutputDecoder, TcntWriteRephasesTheCounter) {
    Timer t(0);
    t.regs.ocra = 100;
    t.start(3, kCs64, 2, 0);
    EXPECT_TRUE(t.write_tcnt(5000, 128));
    EXPECT_FALSE(t.dec.level_at(kA, 5000));
    EXPECT_EQ(t.dec.next_change_after(kA, 5000), 13192u);
    EXPECT_EQ(t.dec.next_change_after(kA, 13192), 19656u);
    t.mode(3, 0, 2, 0);
    t.write(30000);
    t.write_tcnt(30010, 250);
    t.mode(3, kCs64, 2, 0);
    t.write(40000);
    EXPECT_EQ(t.dec.next_change_after(kA, 40000), 40000u + 6u * 64u);  // BOTTOM after 250..255
}

// Stopping the clock freezes the pins: Timer1 mode 1, N = 64, OCR1A 100; at
// 1000 the count is 15 (up) and OC1A high (1000 < 6400). Stopped: constant high.
// Restarted at 50000 the count resumes at 15: falls at 50000 + 85 x 64 = 55440.
TEST(TimerOutputDecoder, StoppedTimerHoldsItsLevel) {
    Timer t(1);
    t.regs.ocra = 100;
    t.start(1, kCs64, 2, 0);
    t.mode(1, 0, 2, 0);
    EXPECT_TRUE(t.write(1000));
    EXPECT_FALSE(t.dec.running());
    EXPECT_TRUE(t.dec.level_at(kA, 40000));
    EXPECT_EQ(t.dec.next_change_after(kA, 1000), kNever);
    EXPECT_EQ(t.dec.period_cycles(kA), 0u);
    EXPECT_DOUBLE_EQ(t.dec.duty(kA), 1.0);
    t.regs.ocra = 10;  // stopped: at once, the pin unchanged
    t.write(2000);
    EXPECT_TRUE(t.dec.level_at(kA, 2000));
    t.regs.ocra = 100;
    t.write(3000);
    t.mode(1, kCs64, 2, 0);
    t.write(50000);
    EXPECT_EQ(t.dec.next_change_after(kA, 50000), 55440u);
    // CS0 = 6: Timer0 clocked from the T0 pin, which nothing drives here.
    Timer e(0);
    e.mode(3, 6, 2, 0);
    e.regs.ocra = 10;
    e.write(0);
    EXPECT_FALSE(e.dec.running());
    EXPECT_EQ(e.dec.next_change_after(kA, 0), kNever);
}

// ---- extremes --------------------------------------------------------------------------

// Fast PWM OCR 0: a one-count spike (64 cycles) per 16384; OCR 255 = TOP:
// constant high. Phase correct OCR 0: constant low; OCR 255: constant high.
TEST(TimerOutputDecoder, AnalogWriteExtremes) {
    Timer t0(0);
    t0.regs.ocra = 0;
    t0.regs.ocrb = 255;
    t0.start(3, kCs64, 2, 2);
    const Measured spike = measure(t0.dec, kA, 0);
    EXPECT_EQ(spike.period, 16384u);
    EXPECT_EQ(spike.high, 64u);
    EXPECT_DOUBLE_EQ(t0.dec.duty(kA), 1.0 / 256.0);
    EXPECT_TRUE(t0.dec.level_at(kB, 12345));
    EXPECT_EQ(t0.dec.next_change_after(kB, 0), kNever);
    EXPECT_EQ(t0.dec.period_cycles(kB), 0u);
    EXPECT_DOUBLE_EQ(t0.dec.duty(kB), 1.0);

    Timer t1(1);
    t1.regs.ocra = 0;
    t1.regs.ocrb = 255;
    t1.start(1, kCs64, 2, 2);
    EXPECT_FALSE(t1.dec.level_at(kA, 12345));
    EXPECT_EQ(t1.dec.next_change_after(kA, 0), kNever);
    EXPECT_TRUE(t1.dec.level_at(kB, 12345));
    EXPECT_EQ(t1.dec.next_change_after(kB, 0), kNever);
}

// analogWrite(10, -30) stores 65506 in OCR1B; Timer1 in mode 1 (TOP 255) never
// matches it. At the TOP update the pin keeps the level of the OCR before:
// low after 100, high after 255. With mask_ocr_to_fixed_top (datasheet
// §15.9.4) the register holds 65506 & 0xFF = 226: duty 226/255, high 2 x 226 x 64
// = 28928 cycles.
TEST(TimerOutputDecoder, OcrAboveTopKeepsTheLevel) {
    for (const uint16_t before : {uint16_t{100}, uint16_t{255}}) {
        Timer t(1);
        t.regs.ocrb = before;
        t.start(1, kCs64, 0, 2);
        t.regs.ocrb = 65506;
        t.write(1000);
        t.dec.advance_to(16320);
        EXPECT_EQ(t.dec.level_at(kB, 20000), before == 255) << before;
        EXPECT_EQ(t.dec.next_change_after(kB, 16320), kNever);
        EXPECT_DOUBLE_EQ(t.dec.duty(kB), before == 255 ? 1.0 : 0.0);
    }
    hil::TimerOutputOptions masked;
    masked.mask_ocr_to_fixed_top = true;
    Timer m(1, masked);
    m.start(1, kCs64, 0, 2);
    m.regs.ocrb = 65506;
    m.write(10);
    m.dec.advance_to(16320);
    EXPECT_EQ(measure(m.dec, kB, 16320).high, 28928u);
    EXPECT_DOUBLE_EQ(m.dec.duty(kB), 226.0 / 255.0);
}

// Timer0 mode 7 with OCR0B (50) > TOP = OCR0A (40): set at BOTTOM, never
// cleared: constant high.
TEST(TimerOutputDecoder, FastPwmOcrAboveTopIsConstantHigh) {
    Timer t(0);
    t.regs.ocra = 40;
    t.regs.ocrb = 50;
    t.start(7, kCs8, 0, 2);
    EXPECT_TRUE(t.dec.level_at(kB, 1000));
    EXPECT_EQ(t.dec.next_change_after(kB, 0), kNever);
    EXPECT_DOUBLE_EQ(t.dec.duty(kB), 1.0);
}

// ICR1 lowered below the count (mode 14, N = 1, ICR1 799 -> 499 at 700, count
// 700): the counter runs on to 0xFFFF and wraps (§15.9.3) at 700 + 65536 - 700
// = 65536. OC1A (OCR1A 199) is low at 700 and stays low until that BOTTOM.
TEST(TimerOutputDecoder, IcrBelowTheCountRunsToMax) {
    Timer t(1);
    t.regs.icr = 799;
    t.regs.ocra = 199;
    t.start(14, kCs1, 2, 0);
    t.regs.icr = 499;
    t.write(700);
    EXPECT_FALSE(t.dec.level_at(kA, 700));
    EXPECT_FALSE(t.dec.level_at(kA, 65535));
    EXPECT_EQ(t.dec.next_change_after(kA, 700), 65536u);
    EXPECT_EQ(t.dec.next_change_after(kA, 65536), 65536u + 200u);
    EXPECT_EQ(measure(t.dec, kA, 65536).period, 500u);
}

// COM tables: 01 on OCnB in PWM modes, and on OCnA unless WGMn2 = 1 (Timer0/2)
// or Timer1 modes 9, 11, 14, 15, is disconnected; reserved modes drive nothing.
TEST(TimerOutputDecoder, ConnectedFollowsTheComTables) {
    Timer t0(0);
    t0.mode(3, kCs64, 1, 1);
    t0.write(0);
    EXPECT_FALSE(t0.dec.connected(kA));
    EXPECT_FALSE(t0.dec.connected(kB));
    t0.mode(7, kCs64, 1, 1);
    t0.write(10);
    EXPECT_TRUE(t0.dec.connected(kA));
    EXPECT_FALSE(t0.dec.connected(kB));
    t0.mode(4, kCs64, 2, 2);  // reserved
    t0.write(20);
    EXPECT_FALSE(t0.dec.connected(kA));
    Timer t1(1);
    Cycles now = 0;
    for (const unsigned wgm : {1U, 5U, 8U, 10U}) {
        t1.mode(wgm, kCs1, 1, 1);
        t1.write(++now);
        EXPECT_FALSE(t1.dec.connected(kA)) << wgm;
    }
    for (const unsigned wgm : {9U, 11U, 14U, 15U}) {
        t1.mode(wgm, kCs1, 1, 1);
        t1.write(++now);
        EXPECT_TRUE(t1.dec.connected(kA)) << wgm;
        EXPECT_FALSE(t1.dec.connected(kB)) << wgm;
    }
    t1.mode(12, kCs1, 1, 1);  // CTC: toggle on both
    t1.write(100);
    EXPECT_TRUE(t1.dec.connected(kB));
}

// ---- bit identity with the decoding it replaces ----------------------------------------

/// motor_driver_reader.cpp's decoding of one bridge's enable pin, re-expressed
/// here on plant::PhaseCorrectPwm (BridgeDrive + sample_registers + advance_to).
struct LegacyBridge {
    using Pwm = plant::PhaseCorrectPwm;
    static constexpr uint16_t kTop = 255;
    static constexpr Cycles kTopOffset = Pwm::kPeriodCycles / 2;
    static constexpr Cycles kPeriod = Pwm::kPeriodCycles;

    bool pwm_connected = false;
    bool timer_running = false;
    uint16_t ocr = 0;
    bool latch_high = false;
    Cycles bottom_cycle = 0;
    uint16_t ocr_written = 0;
    bool ocr_pending = false;
    Cycles ocr_effective_cycle = 0;

    static Cycles next_top_after(Cycles cycle, Cycles bottom) {
        if (cycle < bottom + kTopOffset) return bottom + kTopOffset;
        const Cycles k = (cycle - bottom - kTopOffset) / kPeriod + 1;
        return bottom + kTopOffset + k * kPeriod;
    }
    void sample(Cycles now, bool running, bool com1, uint16_t ocr_now) {
        if (running && !timer_running) bottom_cycle = now;
        timer_running = running;
        pwm_connected = com1;
        if (ocr_now != ocr_written) {
            ocr_written = ocr_now;
            ocr_pending = ocr_now != ocr;
            ocr_effective_cycle = timer_running ? next_top_after(now, bottom_cycle) : now;
        }
    }
    void advance_to(Cycles cycle) {
        if (!ocr_pending || cycle < ocr_effective_cycle) return;
        if (ocr_written > kTop) {
            if (ocr < kTop) latch_high = false;
            else if (ocr == kTop) latch_high = true;
        } else {
            latch_high = ocr_written == kTop;
        }
        ocr = ocr_written;
        ocr_pending = false;
    }
    Pwm wave() const {
        Pwm w;
        w.ocr = static_cast<uint8_t>(ocr);
        w.bottom_cycle = static_cast<int64_t>(bottom_cycle);
        return w;
    }
    bool level_at(Cycles cycle) const {
        if (!timer_running || ocr > kTop) return latch_high;
        return wave().level_at(static_cast<int64_t>(cycle));
    }
    Cycles next_edge_after(Cycles cycle) const {
        if (!timer_running || ocr == 0 || ocr >= kTop) return kNever;
        const int64_t next = wave().next_edge_after(static_cast<int64_t>(cycle));
        return next == Pwm::kNever ? kNever : static_cast<Cycles>(next);
    }
    double duty() const {
        if (!timer_running || ocr > kTop) return latch_high ? 1.0 : 0.0;
        return static_cast<double>(ocr) / static_cast<double>(kTop);
    }
};

/// Random register writes (seeded) on Timer1/OC1B (pin 10) or Timer2/OC2A
/// (pin 11) after Arduino's init(), both decoders advanced alike; level, next
/// edge and duty compared at random cycles and around every edge.
class BitIdentity {
public:
    BitIdentity(int timer, uint64_t seed) : timer_(timer), ch_(timer == 1 ? kB : kA), t_(timer), rng_(seed) {}

    void run(int events) {
        arduino_init();
        Cycles now = 200;
        for (int e = 0; e < events && !::testing::Test::HasFailure(); ++e) {
            const Cycles at = next_event_cycle(now);
            query_until(now, at);
            event(at);
            now = at;
        }
    }
    int compared() const { return compared_; }
    int compared_latched() const { return latched_; }

private:
    uint64_t draw(uint64_t n) { return rng_() % n; }
    uint8_t com_bit() const { return static_cast<uint8_t>(ch_ == kA ? 0x80 : 0x20); }
    uint16_t& ocr() { return ch_ == kA ? t_.regs.ocra : t_.regs.ocrb; }

    void write(Cycles at) {
        legacy_.advance_to(at);  // the HIL advances before each plant step
        legacy_.sample(at, (t_.regs.tccrb & 7U) != 0, (t_.regs.tccra & com_bit()) != 0, ocr());
        t_.write(at);
    }
    /// wiring.c: Timer1 TCCR1B |= CS11, |= CS10, TCCR1A |= WGM10; Timer2
    /// TCCR2B |= CS22, TCCR2A |= WGM20; 5 cycles apart (lds/ori/sts).
    void arduino_init() {
        if (timer_ == 1) {
            t_.regs.tccrb = 0x02;
            write(100);
            t_.regs.tccrb = 0x03;
            write(105);
            t_.regs.tccra = 0x01;
            write(110);
        } else {
            t_.regs.tccrb = 0x04;
            write(100);
            t_.regs.tccra = 0x01;
            write(105);
        }
    }
    Cycles next_event_cycle(Cycles now) {
        switch (draw(4)) {
            case 0: return now + 1 + draw(200);
            case 1: {  // around a TOP
                const Cycles top = LegacyBridge::next_top_after(now, legacy_.bottom_cycle);
                return std::max(now + 1, top - 1 + draw(3));
            }
            default: return now + 1 + draw(40000);
        }
    }
    uint16_t random_ocr() {
        switch (draw(6)) {
            case 0: return 0;
            case 1: return 255;
            case 2: return timer_ == 1 ? static_cast<uint16_t>(65536 - 1 - draw(300)) : 0;  // negative analogWrite
            case 3: return timer_ == 1 ? static_cast<uint16_t>(256 + draw(65280)) : 254;
            default: return static_cast<uint16_t>(1 + draw(254));
        }
    }
    void event(Cycles at) {
        if (draw(10) < 7) {
            ocr() = random_ocr();
        } else {
            t_.regs.tccra = static_cast<uint8_t>(t_.regs.tccra ^ com_bit());
        }
        write(at);
    }
    void query_until(Cycles from, Cycles to) {
        Cycles q = from;
        for (int i = 0; i < 3; ++i) {
            q += draw((to - q) / 2 + 1);
            compare(q);
            const Cycles edge = legacy_.pwm_connected ? legacy_.next_edge_after(q) : kNever;
            if (edge < to) {
                compare(edge - 1);
                compare(edge);
                q = edge;
            }
        }
    }
    void compare(Cycles q) {
        legacy_.advance_to(q);
        t_.dec.advance_to(q);
        ASSERT_EQ(t_.dec.connected(ch_), legacy_.pwm_connected) << "cycle " << q;
        if (!legacy_.pwm_connected) return;
        ASSERT_EQ(t_.dec.level_at(ch_, q), legacy_.level_at(q)) << "cycle " << q << " ocr " << legacy_.ocr;
        ASSERT_EQ(t_.dec.next_change_after(ch_, q), legacy_.next_edge_after(q)) << "cycle " << q;
        ASSERT_EQ(t_.dec.duty(ch_), legacy_.duty()) << "cycle " << q;
        ++compared_;
        if (legacy_.ocr > LegacyBridge::kTop) ++latched_;
    }

    int timer_;
    int ch_;
    Timer t_;
    LegacyBridge legacy_;
    std::mt19937_64 rng_;
    int compared_ = 0;
    int latched_ = 0;
};

TEST(TimerOutputDecoder, BitIdenticalToTheLegacyDecodingOnTimer1Pin10) {
    BitIdentity b(1, 0x5EED0001);
    b.run(20000);
    EXPECT_GT(b.compared(), 30000);
    EXPECT_GT(b.compared_latched(), 2000);  // OCR1B > TOP was exercised
}

TEST(TimerOutputDecoder, BitIdenticalToTheLegacyDecodingOnTimer2Pin11) {
    BitIdentity b(2, 0x5EED0002);
    b.run(20000);
    EXPECT_GT(b.compared(), 30000);
}

// ATmega2560 Timer3 (datasheet 2549Q ch. 17): the third channel. Fast PWM
// 8-bit (mode 5, WGM32 + WGM30), N = 8: period (255 + 1) x 8 = 2048 cycles
// (7.8 kHz at 16 MHz); COM3C = 10 (bits 3:2 of TCCR3A) with OCR3C = 63: high
// for (63 + 1) x 8 = 512 cycles, duty 64/256; OC3A/OC3B disconnected.
TEST(TimerOutputDecoder, Atmega2560Timer3ChannelC) {
    const hil::TimerDesc& t3 = hil::atmega2560_mcu().timers.at(3);
    ASSERT_EQ(t3.channels, 3);
    EXPECT_EQ(t3.ocrc_low, 0x9C);  // OCR3CL
    hil::TimerOutputDecoder dec(t3);
    hil::TimerRegisters r;
    r.tccra = static_cast<uint8_t>((2U << 2U) | 1U);  // COM3C = 10, WGM30
    r.tccrb = static_cast<uint8_t>(1U << 3U);          // WGM32, stopped
    r.ocrc = 63;
    (void)dec.on_write(0, r, false);
    r.tccrb = static_cast<uint8_t>((1U << 3U) | kCs8);
    (void)dec.on_write(0, r, false);
    constexpr int kC = 2;
    EXPECT_TRUE(dec.connected(kC));
    EXPECT_FALSE(dec.connected(kA));
    EXPECT_EQ(dec.period_cycles(kC), 2048u);
    EXPECT_EQ(measure(dec, kC, 0).period, 2048u);
    EXPECT_EQ(measure(dec, kC, 0).high, 512u);
    EXPECT_DOUBLE_EQ(dec.duty(kC), 64.0 / 256.0);
}

}  // namespace
}  // namespace ddmr::test
