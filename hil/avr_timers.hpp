#pragma once
// The ATmega328P's three timer/counters as data: register addresses, the
// clock-select -> prescaler table, the waveform generation mode table and
// the output-compare pins. TimerOutputDecoder (hil/timer_output.hpp) reads
// only this description, so another AVR's timers (the ATmega2560's Timer3/4/5
// are Timer1's twins) are a new table, not new code.
//
// Sources (Atmel ATmega328P datasheet 7810D-AVR-01/15; /work/shared/DRIVERS.md §5):
//   - addresses: register summary (ch. 30 of the full datasheet), data space
//     (I/O address + 0x20, as simavr's avr->data uses); those atmega328p::reg
//     already names are taken from there;
//   - modes: Table 14-8 (Timer0), Table 15-5 (Timer1), Table 17-8 (Timer2);
//   - clock select: Table 14-9, Table 15-6 (Timer0/1), Table 17-9 (Timer2);
//   - pins: Figure 1-1 (OC0A = PD6, OC0B = PD5, OC1A = PB1, OC1B = PB2,
//     OC2A = PB3, OC2B = PD3).

#include <array>
#include <cstdint>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {

/// How the counter runs in one waveform generation mode (WGM).
enum class WaveKind : uint8_t {
    kNormal,            ///< counts 0..MAX, wraps; OCnx acts on compare match
    kCtc,               ///< clear timer on compare: 0..TOP, wraps
    kFastPwm,           ///< single slope 0..TOP: set at BOTTOM, clear on match
    kPhaseCorrect,      ///< dual slope 0..TOP..0, OCRnx updated at TOP
    kPhaseFreqCorrect,  ///< dual slope 0..TOP..0, OCRnx updated at BOTTOM
    kReserved,          ///< Timer0/2 modes 4, 6; Timer1 mode 13
};

/// Where TOP comes from.
enum class TopSource : uint8_t { kFixed, kOcrA, kIcr };

/// When a written OCRnx (and OCRnA used as TOP) reaches the comparator.
enum class OcrUpdate : uint8_t { kImmediate, kAtTop, kAtBottom };

/// One row of a WGM table.
struct WaveformMode {
    WaveKind kind = WaveKind::kReserved;
    TopSource top_source = TopSource::kFixed;
    uint16_t fixed_top = 0;  ///< TOP when top_source == kFixed (MAX in normal and reserved modes)
    OcrUpdate update = OcrUpdate::kImmediate;
    /// COMnA1:0 = 01 toggles OCnA on compare match in this PWM mode (Tables
    /// 14-3/14-6, 15-3/15-4, 17-3/17-6: Timer0/2 with WGMn2 = 1, Timer1 modes
    /// 9, 11, 14, 15); otherwise 01 leaves OCnA disconnected in PWM modes.
    bool com01_toggles_a = false;
};

/// A pin of the chip: port letter and bit (an OCnx pin gets its waveform
/// only while the pin's DDR bit is set).
struct PortBit {
    char port = 'B';
    uint8_t bit = 0;
};

/// Output-compare channels of the largest timer: A, B and C (the
/// ATmega2560's Timer1/3/4/5); the ATmega328P's timers have A and B.
inline constexpr int kMaxOcChannels = 3;

/// One timer/counter of the chip. Addresses are data-space; 0 where absent.
struct TimerDesc {
    int index = 0;  ///< n in TCCRnA, OCnA...
    int bits = 8;   ///< counter width: 8 or 16
    uint16_t tccra = 0;
    uint16_t tccrb = 0;
    uint16_t tcnt_low = 0;
    uint16_t tcnt_high = 0;
    uint16_t ocra_low = 0;
    uint16_t ocra_high = 0;
    uint16_t ocrb_low = 0;
    uint16_t ocrb_high = 0;
    uint16_t ocrc_low = 0;  ///< OCRnC: only where channels == 3
    uint16_t ocrc_high = 0;
    uint16_t icr_low = 0;
    uint16_t icr_high = 0;
    /// CSn2:0 -> prescaler N (one count per N CPU cycles). 0 = no clock:
    /// CS = 0 stops the timer; on Timer0/1, CS = 6/7 clock it from the T0/T1
    /// pin's falling/rising edges, which the HIL does not drive: treated as stopped.
    std::array<uint16_t, 8> prescaler{};
    /// Number of WGM modes: 8 (WGMn2:0, Timer0/2) or 16 (WGM13:0, Timer1).
    int wgm_modes = 8;
    std::array<WaveformMode, 16> modes{};  ///< indexed by WGM (only wgm_modes used)
    int channels = 2;                        ///< output-compare channels: 2 (A, B) or 3 (A, B, C)
    std::array<PortBit, kMaxOcChannels> pins{};  ///< OCnA, OCnB, OCnC (the first `channels`)

    /// MAX: the counter's largest value [counts].
    [[nodiscard]] constexpr uint32_t max() const { return (uint32_t{1} << bits) - 1U; }
};

namespace avr_timers_detail {

constexpr WaveformMode mode(WaveKind kind, TopSource top, uint16_t fixed_top, OcrUpdate update,
                            bool com01_toggles_a = false) {
    WaveformMode m;
    m.kind = kind;
    m.top_source = top;
    m.fixed_top = fixed_top;
    m.update = update;
    m.com01_toggles_a = com01_toggles_a;
    return m;
}

/// Table 14-8 (Timer0) = Table 17-8 (Timer2).
constexpr std::array<WaveformMode, 16> modes_8bit() {
    using K = WaveKind;
    using T = TopSource;
    using U = OcrUpdate;
    std::array<WaveformMode, 16> m{};
    m[0] = mode(K::kNormal, T::kFixed, 0xFF, U::kImmediate);
    m[1] = mode(K::kPhaseCorrect, T::kFixed, 0xFF, U::kAtTop);
    m[2] = mode(K::kCtc, T::kOcrA, 0, U::kImmediate);
    m[3] = mode(K::kFastPwm, T::kFixed, 0xFF, U::kAtBottom);
    m[4] = mode(K::kReserved, T::kFixed, 0xFF, U::kImmediate);
    m[5] = mode(K::kPhaseCorrect, T::kOcrA, 0, U::kAtTop, true);
    m[6] = mode(K::kReserved, T::kFixed, 0xFF, U::kImmediate);
    m[7] = mode(K::kFastPwm, T::kOcrA, 0, U::kAtBottom, true);
    return m;
}

/// Table 15-5 (Timer1).
constexpr std::array<WaveformMode, 16> modes_16bit() {
    using K = WaveKind;
    using T = TopSource;
    using U = OcrUpdate;
    std::array<WaveformMode, 16> m{};
    m[0] = mode(K::kNormal, T::kFixed, 0xFFFF, U::kImmediate);
    m[1] = mode(K::kPhaseCorrect, T::kFixed, 0x00FF, U::kAtTop);
    m[2] = mode(K::kPhaseCorrect, T::kFixed, 0x01FF, U::kAtTop);
    m[3] = mode(K::kPhaseCorrect, T::kFixed, 0x03FF, U::kAtTop);
    m[4] = mode(K::kCtc, T::kOcrA, 0, U::kImmediate);
    m[5] = mode(K::kFastPwm, T::kFixed, 0x00FF, U::kAtBottom);
    m[6] = mode(K::kFastPwm, T::kFixed, 0x01FF, U::kAtBottom);
    m[7] = mode(K::kFastPwm, T::kFixed, 0x03FF, U::kAtBottom);
    m[8] = mode(K::kPhaseFreqCorrect, T::kIcr, 0, U::kAtBottom);
    m[9] = mode(K::kPhaseFreqCorrect, T::kOcrA, 0, U::kAtBottom, true);
    m[10] = mode(K::kPhaseCorrect, T::kIcr, 0, U::kAtTop);
    m[11] = mode(K::kPhaseCorrect, T::kOcrA, 0, U::kAtTop, true);
    m[12] = mode(K::kCtc, T::kIcr, 0, U::kImmediate);
    m[13] = mode(K::kReserved, T::kFixed, 0xFFFF, U::kImmediate);
    m[14] = mode(K::kFastPwm, T::kIcr, 0, U::kAtBottom, true);
    m[15] = mode(K::kFastPwm, T::kOcrA, 0, U::kAtBottom, true);
    return m;
}

constexpr PortBit pin(char port, uint8_t bit) {
    PortBit p;
    p.port = port;
    p.bit = bit;
    return p;
}

/// Timer0 and Timer1: Tables 14-9 and 15-6 (6, 7: external clock on T0/T1).
inline constexpr std::array<uint16_t, 8> kPrescaler01 = {0, 1, 8, 64, 256, 1024, 0, 0};
/// Timer2: Table 17-9 (its own prescaler, with /32 and /128).
inline constexpr std::array<uint16_t, 8> kPrescaler2 = {0, 1, 8, 32, 64, 128, 256, 1024};

constexpr TimerDesc timer0() {
    TimerDesc d;
    d.index = 0;
    d.bits = 8;
    d.tccra = 0x44;
    d.tccrb = 0x45;
    d.tcnt_low = 0x46;
    d.ocra_low = 0x47;
    d.ocrb_low = 0x48;
    d.prescaler = kPrescaler01;
    d.wgm_modes = 8;
    d.modes = modes_8bit();
    d.pins = {pin('D', 6), pin('D', 5), PortBit{}};
    return d;
}

constexpr TimerDesc timer1() {
    TimerDesc d;
    d.index = 1;
    d.bits = 16;
    d.tccra = atmega328p::reg::kTccr1A;  // 0x80
    d.tccrb = atmega328p::reg::kTccr1B;  // 0x81
    d.tcnt_low = 0x84;
    d.tcnt_high = 0x85;
    d.icr_low = 0x86;
    d.icr_high = 0x87;
    d.ocra_low = atmega328p::reg::kOcr1AL;  // 0x88
    d.ocra_high = atmega328p::reg::kOcr1AH;  // 0x89
    d.ocrb_low = atmega328p::reg::kOcr1BL;  // 0x8A
    d.ocrb_high = atmega328p::reg::kOcr1BH;  // 0x8B
    d.prescaler = kPrescaler01;
    d.wgm_modes = 16;
    d.modes = modes_16bit();
    d.pins = {pin('B', 1), pin('B', 2), PortBit{}};
    return d;
}

constexpr TimerDesc timer2() {
    TimerDesc d;
    d.index = 2;
    d.bits = 8;
    d.tccra = atmega328p::reg::kTccr2A;  // 0xB0
    d.tccrb = atmega328p::reg::kTccr2B;  // 0xB1
    d.tcnt_low = 0xB2;
    d.ocra_low = atmega328p::reg::kOcr2A;  // 0xB3
    d.ocrb_low = atmega328p::reg::kOcr2B;  // 0xB4
    d.prescaler = kPrescaler2;
    d.wgm_modes = 8;
    d.modes = modes_8bit();
    d.pins = {pin('B', 3), pin('D', 3), PortBit{}};
    return d;
}

}  // namespace avr_timers_detail

/// Timer0, Timer1, Timer2 of the ATmega328P, indexed by n.
inline constexpr std::array<TimerDesc, 3> kAtmega328pTimers = {
    avr_timers_detail::timer0(), avr_timers_detail::timer1(), avr_timers_detail::timer2()};

}  // namespace ddmr::hil
