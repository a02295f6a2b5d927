#pragma once
// EncoderInjector: drives each encoder output pin of the board's wiring to
// the level the plant's encoder has, and raises each edge at its exact AVR
// cycle, so whatever interrupt the firmware configured on that pin fires as
// on the chip: INT0/INT1 in any sense mode, or a pin-change interrupt
// (PCINT0..23), both emulated by simavr from the pin level. A firmware that
// reads the B channel inside A's ISR reads B's true level at that cycle.
//
// Signals:
//   out  PORTx pin IRQ of each encoder pin (avr_io_getirq, IOPORT): the level
//   in   the pin's interrupt vector "running" IRQ (entry = 1): counts the ISRs
//   reads EICRA/EIMSK, PCICR/PCMSKn and the vectors' pending IRQs: an edge
//        that requests an interrupt (an enabled INTn edge of the configured
//        sense, or a change of a pin in an enabled PCMSKn) while that
//        vector's request is still pending (its flag set, not yet served)
//        cannot start another ISR: it is counted as lost (datasheet 7810D
//        section 12: one flag per request).
//
// The levels are put on the pins by a PinDriver (hil/pin_driver.hpp): its
// queue and cycle timer raise each edge at its cycle, and it restores the
// levels after an AVR reset.

#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board.hpp"
#include "hil/board_description.hpp"
#include "hil/pin_driver.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// Per wheel: all its encoder signals together.
struct EncoderChannelStats {
    uint64_t edges_injected = 0;  ///< edges raised on the wheel's encoder pins
    uint64_t lost_edges = 0;      ///< raised while their interrupt flag was still set
    uint64_t isr_count = 0;       ///< entries into the interrupt vector of the OUT / A pin
    std::optional<Cycles> last_lost_cycle;
};

class EncoderInjector {
public:
    EncoderInjector(AvrCore& core, const BoardWiring& board);
    ~EncoderInjector();
    EncoderInjector(const EncoderInjector&) = delete;
    EncoderInjector& operator=(const EncoderInjector&) = delete;

    /// Puts `level` on the pin of wheel `channel`'s plant signal (0: OUT / A,
    /// 1: B; swapped onto the pins when `reversed`) now, without
    /// counting an edge (the sensor's output at power-on).
    void drive_now(unsigned channel, unsigned signal, bool level);

    /// Queues an edge of wheel `channel` (0, 1), plant signal (0 = OUT / A, 1 = B)
    /// to `level` at `cycle` (not before the last queued edge; an edge at or
    /// before now is raised at once).
    void schedule(unsigned channel, unsigned signal, Cycles cycle, bool level);
    void schedule(unsigned channel, Cycles cycle, bool level) { schedule(channel, 0, cycle, level); }

    /// Called as each edge is put on its pin: the pin, the AVR cycle of the
    /// raise (at or just after the plant's edge time: the first instruction
    /// boundary), the new level. (For VcdRecorder; keep it short, do not throw.)
    void set_edge_listener(std::function<void(int, Cycles, bool)> listener) { edge_listener_ = std::move(listener); }

    const EncoderChannelStats& stats(unsigned channel) const { return stats_[channel]; }
    /// Cycle of each ISR entry of the channel's OUT / A interrupt, in order
    /// (for tests): the first kRecordedIsrEntries only, so long runs keep
    /// their memory flat (isr_count counts them all).
    static constexpr std::size_t kRecordedIsrEntries = 16384;
    const std::vector<Cycles>& isr_entries(unsigned channel) const { return isr_entries_[channel]; }
    /// The interrupt vector (datasheet numbering, RESET = 0) that the pin of
    /// the channel's OUT / A signal can raise: INT0/INT1 on D2/D3, else its
    /// pin-change group's vector (which fires only if the firmware enables it).
    /// The vector the channel's first pin raises; -1: no encoder, or a pin without interrupt (polled).
    int vector_of(unsigned channel) const { return signal_[channel][0].vector; }
    /// The external interrupt (0 = INT0, 1 = INT1) on the channel's OUT / A pin, if any.
    std::optional<int> interrupt_of(unsigned channel) const { return signal_[channel][0].pin.ext_int; }
    /// The level the injector last put on the pin of wheel `channel`'s
    /// encoder signal `pin_signal` (0: OUT / A pin, 1: B pin of the board file).
    bool level(unsigned channel, unsigned pin_signal) const;
    std::size_t pending() const { return driver_.pending(); }

private:
    struct Signal {
        bool used = false;
        PinInfo pin{};
        int vector = -1;
        avr_irq_t* ext_pending = nullptr;    ///< INTn's pending IRQ (D2, D3)
        avr_irq_t* pcint_pending = nullptr;  ///< the pin-change group's pending IRQ
    };
    struct IsrWatch {
        EncoderInjector* self = nullptr;
        unsigned channel = 0;
    };
    static void on_isr(avr_irq_t* irq, uint32_t value, void* param);
    /// Counts an edge the driver is about to put on `pin`, and whether it is lost.
    void before_edge(int pin, Cycles cycle, bool level);
    /// Whether this edge finds its interrupt request still pending.
    bool request_pending(const Signal& s, bool level) const;
    /// The board's pin (0: OUT / A, 1: B) of the plant's signal: swapped when
    /// a quadrature encoder is `reversed` (B leads A going forward).
    unsigned pin_index(unsigned channel, unsigned signal) const;

    AvrCore& core_;
    std::array<std::array<Signal, 2>, 2> signal_{};
    std::array<bool, 2> swapped_{};
    std::array<EncoderChannelStats, 2> stats_{};
    std::array<std::vector<Cycles>, 2> isr_entries_{};
    std::array<IsrWatch, 2> isr_watch_{};
    std::function<void(int, Cycles, bool)> edge_listener_;
    PinDriver driver_;
};

}  // namespace ddmr::hil
