#pragma once
// TimerOutputDecoder: the waveforms one AVR timer puts on its output-compare
// pins OCnA and OCnB, decoded from the timer's registers. simavr 1.6 does not
// emulate phase-correct PWM and its timer pins are unreliable, so the HIL
// computes every output-compare waveform itself. Pure C++ (no simavr): the
// caller passes register values and cycles; the timer is data (avr_timers.hpp).
//
// Signals: in  - on_write(cycle, registers after the write, TCNT written?);
//                advance_to(cycle) applies double-buffered updates;
//          out - per channel: connected, level_at, next_change_after, duty,
//                period_cycles; pending_update_cycle for the plant's stepping.
//
// Model (ATmega328P datasheet 7810D ch. 14, 15, 17; DRIVERS.md §5):
//   counter  - one count per N cycles (N = prescaler of CSn2:0). Single slope
//              (normal, CTC, fast PWM) 0..TOP then 0: period (TOP+1)·N cycles;
//              dual slope (phase correct PC, phase & frequency correct PFC)
//              0..TOP..0: period 2·TOP·N. Position p in [0, period) is counted
//              in cycles from BOTTOM. The counter keeps its count while the clock
//              is stopped (0 after reset) and resumes from it; a TCNT write sets
//              the count at its cycle. Not modelled: the shared prescaler's phase
//              (a start or TCNT write begins a fresh count; a prescaler change
//              keeps the cycles already spent in the current count, capped at N-1),
//              external clocks (CS = 6/7 on Timer0/1: stopped), FOCnx strobes.
//   fast PWM - COM 10: high while count <= OCR, p < (OCR+1)·N; duty (OCR+1)/(TOP+1);
//              OCR = 0 a one-count spike; OCR >= TOP constant high (set at BOTTOM,
//              never cleared). COM 11: the complement.
//   PC, PFC  - COM 10: clear on up-count match, set on down-count match: high
//              for p < OCR·N or p >= period - OCR·N; duty OCR/TOP; OCR = 0 low,
//              OCR = TOP high; OCR > TOP never matches: the level kept is the
//              latch set at each buffer update from the OCR then in effect (at
//              TOP: low if OCR < TOP, high if OCR = TOP; at BOTTOM (PFC): high
//              if 0 < OCR <= TOP, low if 0; unchanged if OCR > TOP). COM 11: complement.
//              PWM levels are a function of p only (stateless), as on the chip
//              one period after a COM or mode change.
//   normal,  - COM 01 toggles, 10 clears, 11 sets OCnx at each compare match
//   CTC        (count reaches OCR, OCR <= TOP); stateful: the OCnx level at the
//              last write plus the matches since. COM 01 on OCnA also toggles in
//              the PWM modes where the table allows it (WaveformMode::com01_toggles_a).
//   held     - COM 00, COM 01 where the tables disconnect it, reserved modes,
//              a stopped timer: the OCnx register keeps its level (connected()
//              tells whether the pin shows it; the caller uses PORT otherwise).
//   buffers  - OCRnx (and OCRnA as TOP) written in PC mode take effect at the
//              first TOP strictly after the write, in fast PWM and PFC at the
//              first BOTTOM strictly after; at once in normal/CTC or while the
//              timer is stopped (a stop applies pending values). ICR1 is not
//              buffered. A write of the value already in effect cancels a pending one.
//   TOP moved- if the count is above a new TOP, the counter runs on to MAX and
//   below the  wraps to BOTTOM (§15.9.3), or, counting down in PC/PFC, runs down
//   count      to TOP; until then the outputs hold their level (a compare match
//              in that stretch is not modelled).
// All queries are O(1) closed forms (no loops over periods, no heap).

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>

#include "hil/avr_timers.hpp"
#include "hil/cycle_time.hpp"

namespace ddmr::hil {

/// All registers of one timer after a write (16-bit ones as the chip holds them).
struct TimerRegisters {
    uint8_t tccra = 0, tccrb = 0;
    uint16_t ocra = 0, ocrb = 0, icr = 0, tcnt = 0;
    uint16_t ocrc = 0;  ///< OCRnC, on timers with three channels
};

/// Choices the datasheet leaves to the emulator.
struct TimerOutputOptions {
    /// Datasheet 7810D §15.9.3/§15.9.4: "when using fixed TOP values, the unused
    /// bits are masked to zero when any of the OCR1x registers are written"
    /// (Timer1 modes 1-3, 5-7). Off by default: simavr keeps the 16-bit value
    /// (OCR1B = 65506 after analogWrite(10, -30)) and today's HIL latches the
    /// level for OCR > TOP. On: the written value is ANDed with the fixed TOP
    /// (65506 -> 226 in 8-bit modes, as Timer2's 8-bit OCR2A wraps).
    bool mask_ocr_to_fixed_top = false;
};

class TimerOutputDecoder {
public:
    static constexpr Cycles kNever = ~Cycles{0};

    explicit TimerOutputDecoder(const TimerDesc& desc, const TimerOutputOptions& options = {});

    /// The firmware wrote the timer's registers at `cycle`; `regs` holds all of
    /// them after the write; tcnt_written: the write was to TCNT (the count jumps
    /// to regs.tcnt at `cycle`). Applies buffered updates due by `cycle` first.
    /// Returns whether the output of either channel may have changed (for latency stats).
    bool on_write(Cycles cycle, const TimerRegisters& regs, bool tcnt_written);
    /// Applies double-buffered OCRx/TOP updates whose update point (TOP or BOTTOM
    /// per mode) has come by `cycle`; returns the cycle of the earliest update
    /// applied since the last call (including those on_write applied), if any.
    /// Called with non-decreasing cycles.
    std::optional<Cycles> advance_to(Cycles cycle);

    /// Channel 0 = A, 1 = B. Whether COMnx connects the output-compare unit to the
    /// pin (per mode, per the COM tables: COM=01 on OCnB in PWM modes is disconnected,
    /// on OCnA only with WGMn2=1 (T0/T2) or T1 modes 9/11/14/15; reserved modes: no).
    [[nodiscard]] bool connected(int ch) const;
    /// The OCnx output level during `cycle` (cycle >= the last on_write/advance_to
    /// cycle), assuming no register change in between (see pending_update_cycle).
    [[nodiscard]] bool level_at(int ch, Cycles cycle) const;
    /// First cycle after `cycle` at which the level changes, or kNever if constant from there.
    [[nodiscard]] Cycles next_change_after(int ch, Cycles cycle) const;
    /// Mean level over one period [0,1] (phase correct: OCR/TOP; fast PWM:
    /// (OCR+1)/(TOP+1); toggle: 0.5; set/clear on match: the level after the
    /// match; constant 0/1).
    [[nodiscard]] double duty(int ch) const;
    /// Waveform period [cycles] (0 when the output is constant).
    [[nodiscard]] Cycles period_cycles(int ch) const;
    /// Clock select != stopped (an external clock counts as stopped).
    [[nodiscard]] bool running() const { return prescaler_ != 0; }
    /// CTC mode (clear timer on compare match).
    [[nodiscard]] bool ctc_mode() const { return mode_.kind == WaveKind::kCtc; }
    /// The waveform generation mode WGMn in effect.
    [[nodiscard]] uint8_t wgm() const { return wgm_; }
    /// A mode that makes PWM (fast, phase correct, phase and frequency correct),
    /// not normal, CTC or a reserved mode.
    [[nodiscard]] bool pwm_mode() const {
        return mode_.kind == WaveKind::kFastPwm || mode_.kind == WaveKind::kPhaseCorrect ||
               mode_.kind == WaveKind::kPhaseFreqCorrect;
    }
    /// When the next pending buffered update takes effect, or kNever.
    [[nodiscard]] Cycles pending_update_cycle() const { return pending_cycle_; }
    /// The waveform generation mode's row (kind, TOP source).
    [[nodiscard]] const WaveformMode& mode() const { return mode_; }

    // The counter's events, for the timer's flags (PhaseCorrectTimer). Each
    // is the first cycle strictly after `cycle` at which the count reaches
    // the value, assuming no register change in between (see
    // pending_update_cycle); kNever while the count does not move.
    /// The count reaches BOTTOM (0).
    [[nodiscard]] Cycles next_bottom_after(Cycles cycle) const;
    /// The count reaches TOP.
    [[nodiscard]] Cycles next_top_after(Cycles cycle) const;
    /// The count reaches OCRnx in effect of channel `ch`: counting up and
    /// (dual slope) down; once a period if OCR is 0 or TOP; never if OCR > TOP.
    [[nodiscard]] Cycles next_compare_match_after(int ch, Cycles cycle) const;
    /// TCNTn during `cycle` (cycle >= the last on_write/advance_to cycle).
    [[nodiscard]] uint16_t count_value_at(Cycles cycle) const {
        return static_cast<uint16_t>(count_at(cycle).value);
    }

private:
    /// The counter: value, direction and cycles already spent in this count.
    struct Count {
        Cycles value = 0;
        bool down = false;
        Cycles sub = 0;
    };
    /// What the waveform generator does to one OCnx.
    enum class Action : uint8_t { kHold, kFastPwm, kPhasePwm, kToggle, kClear, kSet };
    struct Channel {
        uint16_t ocr = 0;          ///< compare value in effect [counts]
        uint16_t ocr_written = 0;  ///< last value the firmware wrote (the buffer)
        bool pending = false;      ///< ocr_written waits for the update point
        uint8_t com = 0;           ///< COMnx1:0
        bool oc = false;           ///< OCnx register level at ref_ (what a held pin shows)
        bool latch = false;        ///< PC/PFC, non-inverted: the level kept while OCR > TOP
    };
    /// Compare-match positions in a period [cycles from BOTTOM]; n = 0: none.
    struct Matches {
        std::array<Cycles, 2> pos{};
        std::size_t n = 0;
    };
    /// What decides the outputs (for on_write's "may have changed").
    struct Shape {
        bool running = false;
        uint8_t wgm = 0;
        std::array<uint8_t, kMaxOcChannels> com{};
        std::array<uint16_t, kMaxOcChannels> ocr{};
        Cycles prescaler = 0;
        Cycles top = 0;
        bool operator==(const Shape& o) const;
    };

    void configure(const TimerRegisters& regs);
    void take_ocr_writes(const TimerRegisters& regs);
    void apply_buffers();
    void update_latch(Channel& h) const;
    void refresh_top();
    void rebase(Cycles cycle, Count count);
    void snapshot_levels(Cycles cycle);
    void reset_latches();
    void schedule_pending(Cycles cycle);
    void apply_due(Cycles cycle);
    void apply_update(Cycles cycle);
    [[nodiscard]] Shape shape() const;
    [[nodiscard]] bool any_pending() const {
        return std::any_of(ch_.begin(), ch_.end(), [](const Channel& h) { return h.pending; });
    }
    [[nodiscard]] bool dual_slope() const;
    [[nodiscard]] bool ticking() const { return period_ != 0; }

    [[nodiscard]] const Channel& chan(int ch) const;
    [[nodiscard]] Action action(int ch) const;
    [[nodiscard]] bool inverting(int ch) const { return chan(ch).com == 3; }
    [[nodiscard]] Cycles pos_at(Cycles cycle) const;
    [[nodiscard]] Cycles position_of(const Count& count) const;
    [[nodiscard]] Count count_at(Cycles cycle) const;
    [[nodiscard]] Count count_from_pos(Cycles pos) const;
    [[nodiscard]] bool pwm_level(const Channel& h, Action a, Cycles pos) const;
    [[nodiscard]] Matches matches_of(int ch) const;
    [[nodiscard]] Cycles matches_through(const Matches& m, Cycles cycle) const;
    [[nodiscard]] Cycles next_at_or_after(Cycles pos, Cycles cycle) const;
    [[nodiscard]] Cycles next_match_after(const Matches& m, Cycles cycle) const;
    [[nodiscard]] Cycles next_position_after(Cycles pos, Cycles cycle) const;
    [[nodiscard]] Cycles next_change_in_regime(int ch, Action a, Cycles cycle) const;
    [[nodiscard]] Cycles next_fast_edge(const Channel& h, Cycles cycle) const;
    [[nodiscard]] Cycles next_phase_edge(const Channel& h, Cycles cycle) const;
    [[nodiscard]] double pwm_duty(const Channel& h, Action a) const;

    TimerDesc desc_;
    TimerOutputOptions options_;
    Cycles max_ = 0;          ///< MAX [counts]
    uint8_t wgm_ = 0;
    WaveformMode mode_{};
    Cycles prescaler_ = 0;    ///< N [cycles per count], 0 = no clock
    Cycles icr_ = 0;          ///< ICR1 [counts]
    Cycles top_ = 0;          ///< TOP in effect [counts]
    Cycles period_ = 0;       ///< [cycles] of one counting period; 0: the count does not move
    Cycles ref_ = 0;          ///< cycle of the last rebase
    Count ref_count_{};       ///< count at ref_ (kept while stopped)
    Cycles regime_start_ = 0; ///< from this cycle on the count is periodic
    Cycles regime_pos_ = 0;   ///< position at regime_start_ [cycles from BOTTOM]
    Cycles match_from_ = 1;   ///< compare matches count from this cycle on
    Cycles pending_cycle_ = kNever;
    std::optional<Cycles> unreported_update_;
    std::array<Channel, kMaxOcChannels> ch_{};  ///< the first desc_.channels in use (the rest held, COM 0)
};

}  // namespace ddmr::hil
