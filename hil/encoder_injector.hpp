#pragma once
// EncoderInjector: raises each Hall-sensor edge the plant reports on the
// encoder's pin at its exact AVR cycle, so the firmware's INT0/INT1 ISRs run
// when they would on the robot.
//
// Signals:
//   out  PORTx pin IRQ of each encoder pin (avr_io_getirq, IOPORT): the level
//   in   INTn vector "running" IRQ (entry = 1): counts the ISRs
//   reads EIFR: an edge raised while its INTFn flag is still set (the
//        previous edge not yet served) cannot start a second ISR: it is lost.
//
// Edges are queued in time order (the plant reports each step's edges sorted,
// steps in order) and served by one cycle timer armed at the earliest.

#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board.hpp"

struct avr_irq_t;

namespace ddmr::hil {

struct EncoderChannelStats {
    uint64_t edges_injected = 0;  ///< edges raised on the pin
    uint64_t lost_edges = 0;      ///< raised while the previous one was pending
    uint64_t isr_count = 0;       ///< entries into the pin's INTn vector
    std::optional<Cycles> last_lost_cycle;
};

class EncoderInjector {
public:
    EncoderInjector(AvrCore& core, const BoardWiring& board);
    ~EncoderInjector();
    EncoderInjector(const EncoderInjector&) = delete;
    EncoderInjector& operator=(const EncoderInjector&) = delete;

    /// Queues an edge of encoder `channel` (0, 1) to level `level` at `cycle`
    /// (not before the last queued edge; an edge at or before now is raised
    /// at once).
    void schedule(unsigned channel, Cycles cycle, bool level);

    /// Called as each edge is put on its pin: channel, the AVR cycle of the
    /// raise (at or just after the plant's edge time: the first instruction
    /// boundary), the new level. (For VcdRecorder; keep it short, do not throw.)
    void set_edge_listener(std::function<void(unsigned, Cycles, bool)> listener) {
        edge_listener_ = std::move(listener);
    }

    const EncoderChannelStats& stats(unsigned channel) const { return stats_[channel]; }
    /// Cycle of each ISR entry of the channel's interrupt, in order (for
    /// tests): the first kRecordedIsrEntries only, so long runs keep their
    /// memory flat (isr_count counts them all).
    static constexpr std::size_t kRecordedIsrEntries = 16384;
    const std::vector<Cycles>& isr_entries(unsigned channel) const { return isr_entries_[channel]; }
    /// The external interrupt (0 = INT0, 1 = INT1) on the channel's pin, if any.
    std::optional<int> interrupt_of(unsigned channel) const { return interrupt_[channel]; }
    std::size_t pending() const { return queue_.size(); }

private:
    struct Edge {
        Cycles cycle;
        unsigned channel;
        bool level;
    };
    static uint64_t on_timer(struct avr_t* avr, uint64_t when, void* param);
    static void on_isr(avr_irq_t* irq, uint32_t value, void* param);
    void raise(const Edge& e);
    struct IsrWatch {
        EncoderInjector* self = nullptr;
        unsigned channel = 0;
    };

    AvrCore& core_;
    std::array<avr_irq_t*, 2> pin_irq_{};
    std::array<uint16_t, 2> pin_register_{};  ///< PINx data-space address
    std::array<int, 2> pin_bit_{};
    std::array<std::optional<int>, 2> interrupt_{};
    std::array<EncoderChannelStats, 2> stats_{};
    std::array<std::vector<Cycles>, 2> isr_entries_{};
    std::array<IsrWatch, 2> isr_watch_{};
    std::deque<Edge> queue_;
    std::function<void(unsigned, Cycles, bool)> edge_listener_;
    bool armed_ = false;
};

}  // namespace ddmr::hil
