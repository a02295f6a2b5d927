#pragma once
// MotorDriverReader: what the firmware drives on each L298 bridge, decoded
// from the timer and port registers (simavr 1.6 does not emulate 8-bit
// phase-correct PWM, the mode Arduino's init() gives Timers 1 and 2).
//
// Signals (simavr iomem notifications, after each write): TCCRnA (COM bits),
// TCCRnB (clock select), OCRnx, and the PORT registers of the enable and
// direction pins of the board's wiring.
//
// The decoded drive, per bridge, follows the ATmega328P datasheet (15.9.4,
// 18.7.4: phase-correct PWM, non-inverting, COMnx1 = 1):
//   - COMnx1 clear: the enable pin is a plain output at its PORT bit
//     (analogWrite(pin, 0/255) and digitalWrite do this);
//   - COMnx1 set: the pin is the waveform: high while TCNT < OCR on the
//     0..255..0 count (period 2 x 255 x 64 = 32,640 cycles, 490.2 Hz);
//     OCR = 0 continuously low, OCR = 255 (TOP) continuously high;
//   - OCR is double-buffered: a write takes effect at the next TOP;
//   - OCR > 255 (a negative analogWrite on Timer1's 16-bit OCR1B: -30 is
//     stored as 65506) never matches the 8-bit count, so the pin keeps the
//     level it had at the TOP where the value was loaded: low after any OCR
//     below TOP, high after OCR = TOP. Timer2's 8-bit OCR2A wraps instead
//     (-30 -> 226: 88.6 % duty). Whatever the firmware writes is what the
//     robot gets;
//   - the counter starts at BOTTOM when TCCRnB's clock select leaves 0 (the
//     shared prescaler's phase, at most 63 cycles, is not modelled).
// The direction pin is its PORT bit (high = forward). DDR is not checked.

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board.hpp"
#include "plant/pwm_waveform.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// The drive of one bridge over an interval in which no register changes.
struct BridgeDrive {
    bool pwm_connected = false;   ///< COMnx1 set: the timer drives the enable pin
    bool timer_running = false;   ///< TCCRnB clock select != 0
    uint16_t ocr = 0;             ///< OCR in effect (after the TOP update)
    bool latch_high = false;      ///< output level kept while OCR > TOP
    bool port_level = false;      ///< enable pin's PORT bit (used when not PWM)
    bool forward = false;         ///< direction pin's PORT bit
    Cycles bottom_cycle = 0;      ///< a cycle at which the counter was at BOTTOM

    /// Mean enable level over a PWM period, [0, 1] (the averaged model's duty).
    double duty() const;
    /// The 8-bit value analogWrite's waveform uses (for logging): OCR clamped.
    uint8_t duty_u8() const;
    /// Enable pin level during `cycle`.
    bool enable_level_at(Cycles cycle) const;
    /// First cycle after `cycle` at which the enable level changes, or
    /// kNoEdge when it is constant.
    Cycles next_enable_edge_after(Cycles cycle) const;
    static constexpr Cycles kNoEdge = ~Cycles{0};
};

class MotorDriverReader {
public:
    MotorDriverReader(AvrCore& core, const BoardWiring& board);
    ~MotorDriverReader();
    MotorDriverReader(const MotorDriverReader&) = delete;
    MotorDriverReader& operator=(const MotorDriverReader&) = delete;

    /// Applies OCR updates whose TOP has come by `cycle`. Call with
    /// non-decreasing cycles before reading drive().
    void advance_to(Cycles cycle);
    /// The drive of motor `m` (0: motor 1, 1: motor 2) as of the last advance_to.
    const BridgeDrive& drive(std::size_t m) const { return bridge_[m].drive; }
    /// Register writes that changed a bridge's drive so far.
    uint64_t changes() const { return changes_; }
    /// The cycle of the first drive change since the last call (an OCR
    /// update counts at its TOP), or nullopt: for measuring input latency.
    std::optional<Cycles> take_first_change() {
        auto c = first_change_;
        first_change_.reset();
        return c;
    }

private:
    struct Bridge {
        MotorWiring wiring;
        PwmChannel channel;
        PinLocation enable;
        PinLocation direction;
        BridgeDrive drive;
        uint16_t ocr_written = 0;      ///< last value the firmware wrote
        bool ocr_pending = false;
        Cycles ocr_effective_cycle = 0;
    };
    static void on_register(avr_irq_t* irq, uint32_t value, void* param);
    void sample_registers();
    uint16_t read_ocr(const Bridge& b) const;

    AvrCore& core_;
    std::array<Bridge, 2> bridge_{};
    uint64_t changes_ = 0;
    std::optional<Cycles> first_change_;
    void note_change(Cycles cycle) {
        ++changes_;
        if (!first_change_) first_change_ = cycle;
    }
};

}  // namespace ddmr::hil
