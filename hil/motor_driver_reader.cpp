#include "hil/motor_driver_reader.hpp"

#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

using Pwm = plant::PhaseCorrectPwm;
constexpr uint16_t kTop = static_cast<uint16_t>(Pwm::kTop);
/// The counter is at TOP half a period after BOTTOM.
constexpr Cycles kTopOffset = static_cast<Cycles>(Pwm::kPeriodCycles / 2);
constexpr Cycles kPeriod = static_cast<Cycles>(Pwm::kPeriodCycles);

bool port_bit(const AvrCore& core, const PinLocation& pin) {
    return ((static_cast<unsigned>(core.data(pin.port_register)) >> pin.bit) & 1U) != 0;
}

/// The first TOP strictly after `cycle` for a counter at BOTTOM at `bottom`.
Cycles next_top_after(Cycles cycle, Cycles bottom) {
    if (cycle < bottom + kTopOffset) return bottom + kTopOffset;
    const Cycles k = (cycle - bottom - kTopOffset) / kPeriod + 1;
    return bottom + kTopOffset + k * kPeriod;
}

}  // namespace

double BridgeDrive::duty() const {
    if (!pwm_connected) return port_level ? 1.0 : 0.0;
    if (!timer_running) return latch_high ? 1.0 : 0.0;
    if (ocr > kTop) return latch_high ? 1.0 : 0.0;
    return static_cast<double>(ocr) / static_cast<double>(kTop);
}

uint8_t BridgeDrive::duty_u8() const {
    return static_cast<uint8_t>(std::lround(duty() * static_cast<double>(kTop)));
}

bool BridgeDrive::enable_level_at(Cycles cycle) const {
    if (!pwm_connected) return port_level;
    if (!timer_running || ocr > kTop) return latch_high;
    Pwm w;
    w.ocr = static_cast<uint8_t>(ocr);
    w.bottom_cycle = static_cast<int64_t>(bottom_cycle);
    return w.level_at(static_cast<int64_t>(cycle));
}

Cycles BridgeDrive::next_enable_edge_after(Cycles cycle) const {
    if (!pwm_connected || !timer_running || ocr == 0 || ocr >= kTop) return kNoEdge;
    Pwm w;
    w.ocr = static_cast<uint8_t>(ocr);
    w.bottom_cycle = static_cast<int64_t>(bottom_cycle);
    const int64_t next = w.next_edge_after(static_cast<int64_t>(cycle));
    return next == Pwm::kNever ? kNoEdge : static_cast<Cycles>(next);
}

MotorDriverReader::MotorDriverReader(AvrCore& core, const BoardWiring& board) : core_(core) {
    validate(board, "board");
    std::set<uint16_t> registers;
    for (std::size_t m = 0; m < bridge_.size(); ++m) {
        Bridge& b = bridge_[m];
        b.wiring = board.motor[m];
        b.channel = *uno_pwm_channel(b.wiring.enable_pin);
        b.enable = *uno_pin_location(b.wiring.enable_pin);
        b.direction = *uno_pin_location(b.wiring.direction_pin);
        registers.insert({b.channel.tccra, b.channel.tccrb, b.channel.ocr_low, b.enable.port_register,
                          b.direction.port_register});
        if (b.channel.ocr_high != 0) registers.insert(b.channel.ocr_high);
    }
    for (const uint16_t addr : registers) {
        avr_irq_t* irq = avr_iomem_getirq(core_.raw(), addr, nullptr, AVR_IOMEM_IRQ_ALL);
        if (irq == nullptr) throw std::runtime_error("simavr gave no IRQ for register " + std::to_string(addr));
        avr_irq_register_notify(irq, &MotorDriverReader::on_register, this);
    }
    sample_registers();
    // An AVR reset clears the timer and port registers without a write
    // notification: read them again (timers stopped, PWM disconnected).
    core_.add_reset_listener(this, [this] { sample_registers(); });
}

MotorDriverReader::~MotorDriverReader() { core_.remove_reset_listener(this); }

void MotorDriverReader::on_register(avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
    static_cast<MotorDriverReader*>(param)->sample_registers();
}

uint16_t MotorDriverReader::read_ocr(const Bridge& b) const {
    uint16_t v = core_.data(b.channel.ocr_low);
    if (b.channel.ocr_high != 0) v = static_cast<uint16_t>(v | (core_.data(b.channel.ocr_high) << 8));
    return v;
}

void MotorDriverReader::sample_registers() {
    const Cycles now = core_.cycle();
    for (Bridge& b : bridge_) {
        BridgeDrive& d = b.drive;
        const BridgeDrive before = d;
        const bool running = (core_.data(b.channel.tccrb) & atmega328p::kClockSelectMask) != 0;
        if (running && !d.timer_running) d.bottom_cycle = now;  // the count starts at BOTTOM
        d.timer_running = running;
        d.pwm_connected = (core_.data(b.channel.tccra) & b.channel.com1_mask) != 0;
        d.port_level = port_bit(core_, b.enable);
        d.forward = port_bit(core_, b.direction);
        const uint16_t ocr = read_ocr(b);
        if (ocr != b.ocr_written) {
            b.ocr_written = ocr;
            b.ocr_pending = ocr != d.ocr;
            b.ocr_effective_cycle = d.timer_running ? next_top_after(now, d.bottom_cycle) : now;
        }
        if (d.pwm_connected != before.pwm_connected || d.port_level != before.port_level ||
            d.forward != before.forward || d.timer_running != before.timer_running) {
            note_change(now);
        }
    }
}

void MotorDriverReader::advance_to(Cycles cycle) {
    for (Bridge& b : bridge_) {
        if (!b.ocr_pending || cycle < b.ocr_effective_cycle) continue;
        BridgeDrive& d = b.drive;
        // At TOP the count (255) is above any OCR < TOP: the output is low
        // there; OCR = TOP holds it high; OCR > TOP keeps whatever it was.
        if (b.ocr_written > kTop) {
            if (d.ocr < kTop) d.latch_high = false;
            else if (d.ocr == kTop) d.latch_high = true;
        } else {
            d.latch_high = b.ocr_written == kTop;
        }
        d.ocr = b.ocr_written;
        b.ocr_pending = false;
        note_change(b.ocr_effective_cycle);
    }
}

}  // namespace ddmr::hil
