#include "hil/pin_driver.hpp"

#include "hil/simavr_io.hpp"

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>
#include <string>

namespace ddmr::hil {
namespace {

/// simavr's I/O port `letter` (its "external" levels are per port, shared
/// by every part driving a pin of it), or nullptr.
avr_ioport_t* ioport_of(avr_t* avr, char letter) {
    for (avr_io_t* io : simavr_io_modules(avr, "port")) {
        // avr_ioport_t starts with its avr_io_t (avr_ioport.h).
        auto* port = reinterpret_cast<avr_ioport_t*>(io);
        if (port->name == letter) return port;
    }
    return nullptr;
}

/// Declares (or, with `held` false, withdraws) `level` as the external level
/// of the port bit: what simavr 1.6 re-raises on the input pin after each
/// PORTx / DDRx write instead of the pull-up's 1. (The fields the
/// AVR_IOCTL_IOPORT_SET_EXTERNAL ioctl sets, read back first: the ioctl sets
/// the whole port, and other drivers hold other bits of it.)
void set_external(avr_ioport_t* port, int bit_index, bool held, bool level) {
    const auto bit = static_cast<uint8_t>(1U << static_cast<unsigned>(bit_index));
    uint8_t& mask = port->external.pull_mask;
    uint8_t& value = port->external.pull_value;
    mask = held ? static_cast<uint8_t>(mask | bit) : static_cast<uint8_t>(mask & ~bit);
    value = held && level ? static_cast<uint8_t>(value | bit) : static_cast<uint8_t>(value & ~bit);
}

}  // namespace

PinDriver::PinDriver(AvrCore& core) : core_(core), pins_(static_cast<std::size_t>(core.board().pin_count())) {
    core_.add_reset_listener(this, [this] { restore_after_reset(); });
    core_.allow_replay(ReplayableTimer{&PinDriver::on_timer, this,
                                       [this](const LoopSpan& span) { return edges_replayable(span); },
                                       ReplayableTimer::Runs::kAfterJump});
}

PinDriver::~PinDriver() {
    core_.forget_replay(this);
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(core_.raw(), &PinDriver::on_timer, this);
    for (const Driven& d : pins_) {
        if (d.used) set_external(d.port, d.info.bit, false, false);
    }
}

PinDriver::Driven& PinDriver::driven(int pin) {
    const auto info = board_pin(core_.board(), pin);
    if (!info) {
        throw std::invalid_argument("PinDriver: board " + std::string(core_.board().key) + " has no pin " +
                                    std::to_string(pin) + " (pins " + pin_range(core_.board()) + ")");
    }
    Driven& d = pins_[static_cast<std::size_t>(pin)];
    if (d.used) return d;
    d.info = *info;
    d.irq = avr_io_getirq(core_.raw(), static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(info->port)), info->bit);
    d.port = ioport_of(core_.raw(), info->port);
    if (d.irq == nullptr || d.port == nullptr) {
        throw std::runtime_error("PinDriver: simavr has no port " + std::string(1, info->port) + " for pin " +
                                 std::to_string(pin));
    }
    d.reach = PinEdgeReach(core_.raw(), core_.mcu(), *info);
    d.used = true;
    return d;
}

bool PinDriver::edges_replayable(const LoopSpan& span) const {
    const avr_t* avr = core_.raw();
    return std::all_of(queue_.begin(), queue_.end(), [&](const Edge& e) {
        return pins_[static_cast<std::size_t>(e.pin)].reach.replayable(avr, span, e.level);
    });
}

void PinDriver::put(Driven& d, bool level) {
    set_external(d.port, d.info.bit, true, level);
    avr_raise_irq(d.irq, level ? 1 : 0);
}

void PinDriver::drive_now(int pin, bool level) { put(driven(pin), level); }

bool PinDriver::drives(int pin) const {
    return pin >= 0 && static_cast<std::size_t>(pin) < pins_.size() && pins_[static_cast<std::size_t>(pin)].used;
}

bool PinDriver::level(int pin) const { return drives(pin) && pins_[static_cast<std::size_t>(pin)].irq->value != 0; }

void PinDriver::schedule(int pin, Cycles cycle, bool level) {
    (void)driven(pin);  // validates the pin now, not when the edge is due
    const Edge e{cycle, pin, level};
    // After every queued edge of the same or an earlier cycle: in order.
    const auto at = std::upper_bound(queue_.begin(), queue_.end(), cycle,
                                     [](Cycles c, const Edge& q) { return c < q.cycle; });
    queue_.insert(at, e);
    arm();
}

void PinDriver::cancel_all() {
    queue_.clear();
    if (armed_) avr_cycle_timer_cancel(core_.raw(), &PinDriver::on_timer, this);
    armed_ = false;
}

void PinDriver::arm() {
    if (queue_.empty()) return;
    const Cycles first = queue_.front().cycle;
    if (armed_ && first >= armed_at_) return;  // the timer already covers it
    if (armed_) avr_cycle_timer_cancel(core_.raw(), &PinDriver::on_timer, this);
    const Cycles now = core_.cycle();
    armed_ = true;
    armed_at_ = first;
    avr_cycle_timer_register(core_.raw(), first > now ? first - now : 0, &PinDriver::on_timer, this);
}

uint64_t PinDriver::on_timer(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<PinDriver*>(param);
    // While serving, schedule() must not arm a second timer: this one's
    // return value re-arms it at the new first edge.
    self->armed_at_ = 0;
    while (!self->queue_.empty() && self->queue_.front().cycle <= when) {
        const Edge e = self->queue_.front();
        self->queue_.pop_front();
        const Cycles now = self->core_.cycle();
        if (self->before_edge_) self->before_edge_(e.pin, now, e.level);
        self->put(self->pins_[static_cast<std::size_t>(e.pin)], e.level);
        if (self->after_edge_) self->after_edge_(e.pin, now, e.level);
    }
    if (self->queue_.empty()) {
        self->armed_ = false;
        return 0;
    }
    self->armed_at_ = self->queue_.front().cycle;
    return self->armed_at_;
}

void PinDriver::restore_after_reset() {
    // avr_reset clears PINx and cancels every cycle timer; the parts still
    // drive their pins.
    for (const Driven& d : pins_) {
        if (!d.used) continue;
        uint8_t& pin = core_.raw()->data[d.info.pin_register];
        const auto mask = static_cast<uint8_t>(1U << static_cast<unsigned>(d.info.bit));
        pin = d.irq->value != 0 ? static_cast<uint8_t>(pin | mask) : static_cast<uint8_t>(pin & ~mask);
    }
    armed_ = false;
    arm();
}

}  // namespace ddmr::hil
