#pragma once
// PinDriver: an external part driving the level of board pins, now or at
// exact future AVR cycles. Each level is put on the pin's simavr IOPORT IRQ,
// so whatever the firmware configured on the pin reacts as on the chip:
// PINx reads the level, an INTn edge of the configured sense or a change on
// a pin enabled in PCMSKn raises its interrupt at the cycle of the edge
// (datasheet 7810D section 12 "External Interrupts", 13.2.4 "Reading the Pin
// Value").
//
// Signals:
//   out  avr_io_getirq(AVR_IOCTL_IOPORT_GETIRQ(port), bit) of each driven pin
//   out  AVR_IOCTL_IOPORT_SET_EXTERNAL(port): the driven level of each pin
//        this driver has driven, so simavr 1.6 keeps it (see below)
//
// Timing: edges wait in one queue, in cycle order (edges of the same cycle in
// the order scheduled), served by one simavr cycle timer armed at the
// earliest. simavr runs a cycle timer at the first instruction boundary at or
// after its cycle: an edge due inside a multi-cycle instruction is raised
// when that instruction ends (the chip samples pins every clock, but it also
// serves an interrupt only after the instruction in progress, section 7.7).
//
// simavr 1.6 (avr_ioport.c, avr_ioport_update_irqs) re-raises every input
// pin whose PORT bit is 1 to level 1 on each write to that port's PORTx or
// DDRx, which would overwrite a low that a part drives against the pull-up
// (a pressed bumper on INPUT_PULLUP). The driver declares the driven level
// as the pin's "external" level (the SET_EXTERNAL ioctl, kept per port for
// every PinDriver on that port), so simavr re-raises the driven level
// instead: the part wins over the 20-50 kOhm pull-up, as on the chip
// (section 13.2.1; DC characteristics 28.2, RPU).
//
// Fast-forward: the edge timer is replayable after a jump (ReplayableTimer,
// kAfterJump) while no queued edge can be seen by the skipped passes
// (PinEdgeReach: the pin not read, no interrupt enabled on it), so a wired
// encoder the sketch never reads does not end every jump. The queue is
// checked whole: a part's step may queue edges while the timer is held.
//
// An AVR reset cancels the cycle timer and clears PINx: the driver puts its
// levels back on the pins and re-arms for the queued edges.
// Not thread-safe (like AvrCore). Construct after the AvrCore, destroy before.

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board_description.hpp"
#include "hil/pin_edge_reach.hpp"

struct avr_irq_t;
struct avr_ioport_t;

namespace ddmr::hil {

class PinDriver {
public:
    /// (pin, cycle, level): an edge about to be, or just, put on its pin.
    using EdgeListener = std::function<void(int, Cycles, bool)>;

    /// Drives nothing until drive_now() or schedule() names a pin.
    explicit PinDriver(AvrCore& core);
    ~PinDriver();
    PinDriver(const PinDriver&) = delete;
    PinDriver& operator=(const PinDriver&) = delete;

    /// Puts `level` on board pin `pin` now (no edge listener is called).
    /// Throws std::invalid_argument naming the pin if the board has no such pin.
    void drive_now(int pin, bool level);
    /// Queues `level` on `pin` at `cycle`; an edge at or before now is raised
    /// at the next instruction boundary. Edges may be scheduled in any order.
    void schedule(int pin, Cycles cycle, bool level);
    /// Forgets every queued edge (the levels already driven stay).
    void cancel_all();

    /// Called for each scheduled edge right before its level is put on the
    /// pin (the interrupt flags still show the state before the edge), and
    /// right after. Keep them short; they must not throw.
    void set_before_edge(EdgeListener listener) { before_edge_ = std::move(listener); }
    void set_after_edge(EdgeListener listener) { after_edge_ = std::move(listener); }

    /// Whether this driver has driven `pin`, and the level it last put there.
    [[nodiscard]] bool drives(int pin) const;
    [[nodiscard]] bool level(int pin) const;
    /// The edges queued and not yet raised.
    [[nodiscard]] std::size_t pending() const { return queue_.size(); }
    /// The cycle of the next queued edge; only if pending() > 0.
    [[nodiscard]] Cycles next_edge_cycle() const { return queue_.front().cycle; }

private:
    struct Edge {
        Cycles cycle;
        int pin;
        bool level;
    };
    struct Driven {
        bool used = false;
        PinInfo info{};
        avr_irq_t* irq = nullptr;
        avr_ioport_t* port = nullptr;  ///< simavr's port: its external levels
        PinEdgeReach reach;            ///< what an edge on it reaches (fast-forward)
    };
    static uint64_t on_timer(struct avr_t* avr, uint64_t when, void* param);
    Driven& driven(int pin);
    void put(Driven& d, bool level);
    void arm();
    void restore_after_reset();
    /// True if every queued edge may be raised after a fast-forward jump over `span`.
    [[nodiscard]] bool edges_replayable(const LoopSpan& span) const;

    AvrCore& core_;
    std::vector<Driven> pins_;  ///< per board pin number
    std::deque<Edge> queue_;    ///< in cycle order
    bool armed_ = false;
    Cycles armed_at_ = 0;
    EdgeListener before_edge_;
    EdgeListener after_edge_;
};

}  // namespace ddmr::hil
