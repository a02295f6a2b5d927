#pragma once
// PinWaveforms: the level the chip puts on each watched pin, as a function
// of the cycle, decoded from the port and timer registers (simavr 1.6 does
// not emulate phase-correct PWM and drives no OC pins reliably, so every
// output-compare waveform is decoded here from the datasheet: timer_output.hpp).
//
// Per pin (datasheet 7810D section 13.2.1 "Configuring the Pin", 14.5/15.7/
// 17.5 "Compare Match Output Unit"):
//   DDR = 1, the pin's OC unit connected by COMnx : the timer's waveform
//   DDR = 1, otherwise                             : the PORT bit (static)
//   DDR = 0, PORT = 1, PUD = 0                     : input with the pull-up on
//   DDR = 0, PORT = 0 (or PUD = 1 in MCUCR)        : floating input
// (the port bits decoded by pin_state(), hil/pin_probe.hpp).
// What a part connected to an input pin reads (pull-up, a pull-down of its
// own, floating) is the part's business (MotorDriverReader).
//
// Signals (simavr iomem notifications, after each access): DDRx and PORTx of
// the ports of watched pins, MCUCR (PUD); TCCRnA/B, OCRnA/B and ICR1 of the timers whose
// OC units sit on watched pins. TCNT writes are not followed: the counter's
// phase is taken from the cycle its clock was started (the PWM duty and
// frequency are exact; the phase within a period may differ after a
// firmware writes TCNTn).

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/timer_output.hpp"
#include "hil/board_description.hpp"

struct avr_irq_t;

namespace ddmr::hil {

enum class PinMode : uint8_t { output, input_pullup, input_floating };

class PinWaveforms {
public:
    static constexpr Cycles kNever = TimerOutputDecoder::kNever;

    /// Watches `pins` (the board's pin numbers, each valid) and the timers behind them.
    PinWaveforms(AvrCore& core, const std::vector<int>& pins);
    ~PinWaveforms();
    PinWaveforms(const PinWaveforms&) = delete;
    PinWaveforms& operator=(const PinWaveforms&) = delete;

    /// Called whenever a watched pin's mode or PORT level changes (a register
    /// write, a reset), once this part has sampled it: level_at() gives the
    /// new level. One listener; nullptr removes it. (A VCD follows the pins
    /// through it: simavr calls the parts watching a register last-added
    /// first, so a part of its own watching PORTx would run before this one.)
    void set_port_listener(std::function<void()> listener) { port_listener_ = std::move(listener); }

    /// Applies double-buffered OCR/TOP updates due by `cycle` (non-decreasing).
    void advance_to(Cycles cycle);

    [[nodiscard]] PinMode mode(int pin) const { return pin_[static_cast<std::size_t>(pin)].mode; }
    /// An output whose OC unit drives it.
    [[nodiscard]] bool timer_driven(int pin) const;
    /// Output: its level during `cycle` (cycle >= the last advance_to);
    /// input: whether the pull-up is on (PORT bit set, PUD clear).
    [[nodiscard]] bool level_at(int pin, Cycles cycle) const;
    /// First cycle after `cycle` at which level_at changes, or kNever.
    [[nodiscard]] Cycles next_change_after(int pin, Cycles cycle) const;
    /// Mean of level_at over a period of the waveform, [0, 1].
    [[nodiscard]] double duty(int pin) const;
    /// Whether the firmware ever made the pin an output (DDR bit set).
    [[nodiscard]] bool ever_output(int pin) const { return pin_[static_cast<std::size_t>(pin)].ever_output; }
    /// The timer decoder behind the pin's OC unit, if the pin has one and it is watched.
    [[nodiscard]] const TimerOutputDecoder* timer_of(int pin) const;

    /// A pin whose timer the firmware took over: the pin's compare output
    /// was switched on (analogWrite) while its timer ran in a mode that makes
    /// no PWM (normal or CTC: the Servo library puts Timer1 in normal mode),
    /// for at least kTakeoverMinCycles (a firmware setting a timer up
    /// register by register passes through such states for a few cycles).
    struct Takeover {
        Cycles since = 0;  ///< the first such stretch's start
        uint8_t wgm = 0;   ///< the timer's mode then
        bool ctc = false;  ///< that mode is CTC (else normal)
        int timer = 0;     ///< n of Timer n
        char channel = 'A';  ///< the pin's OCnx
    };
    static constexpr Cycles kTakeoverMinCycles = 16000;  ///< 1 ms at 16 MHz
    /// The pin's first takeover so far (a stretch still running counts once
    /// it is long enough), if any.
    [[nodiscard]] std::optional<Takeover> takeover(int pin) const;

    /// Increases whenever anything a pin's waveform depends on may have
    /// changed (a register value, a buffered update applied): for caches.
    [[nodiscard]] uint64_t revision() const { return revision_; }
    /// Register accesses that changed a watched pin's drive so far (a
    /// buffered OCR update counts at its TOP or BOTTOM).
    [[nodiscard]] uint64_t changes() const { return changes_; }
    /// The cycle of the first drive change since the last call, or nullopt:
    /// for measuring input latency.
    std::optional<Cycles> take_first_change() {
        auto c = first_change_;
        first_change_.reset();
        return c;
    }

private:
    struct Pin {
        bool watched = false;
        PinInfo info{};
        PinMode mode = PinMode::input_floating;
        bool port_bit = false;
        bool ever_output = false;
        bool connected = false;  ///< output and COM connects the OC unit
        std::optional<Takeover> takeover_open;  ///< a stretch without PWM is running
        std::optional<Takeover> takeover;       ///< the first stretch long enough
    };
    struct Hook {
        PinWaveforms* self = nullptr;
        int timer = -1;  ///< -1: a port register
    };
    static void on_register(avr_irq_t* irq, uint32_t value, void* param);
    void watch(uint16_t address, Hook* hook);
    void sample_ports();
    void sample_timer(std::size_t t);
    /// Updates each pin's `connected`; true if one changed.
    bool refresh_connections();
    void track_takeover(Pin& p, const TimerOutputDecoder* t, bool connected);
    void note_change(Cycles cycle);

    AvrCore& core_;
    const std::vector<TimerDesc>& timers_;  ///< the MCU's timers
    std::vector<Pin> pin_;                   ///< per board pin
    std::vector<std::optional<TimerOutputDecoder>> timer_;  ///< per timer: decoded when a watched pin is on it
    std::vector<TimerRegisters> last_regs_;
    std::vector<Hook> timer_hook_;           ///< per timer (never resized: simavr holds pointers)
    Hook port_hook_{};
    uint64_t changes_ = 0;
    uint64_t revision_ = 0;
    std::function<void()> port_listener_;
    std::optional<Cycles> first_change_;
};

}  // namespace ddmr::hil
