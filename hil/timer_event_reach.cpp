#include "hil/timer_event_reach.hpp"

#include <avr_timer.h>
#include <sim_avr.h>

#include "hil/board_description.hpp"
#include "hil/fast_forward.hpp"
#include "hil/mcu.hpp"

namespace ddmr::hil {
namespace {

static_assert(TimerEventReach::kUnits == AVR_TIMER_COMP_COUNT, "simavr's compare units");

const avr_timer_t& timer_of(const void* t) { return *static_cast<const avr_timer_t*>(t); }

/// The register field `bits` names (0 if it names none).
unsigned field(const avr_t* avr, const avr_regbit_t& bits) {
    return bits.reg == 0 ? 0U : (avr->data[bits.reg] >> bits.bit) & bits.mask;
}

bool enabled(const avr_t* avr, const avr_regbit_t& bit) { return field(avr, bit) != 0; }

/// True if a pass may use the flag `bit` names (hil/io_bit_use.hpp).
bool flag_read(const avr_regbit_t& bit, const LoopSpan& span) {
    return bit.reg != 0 && span.reads_bit(bit.reg, bit.bit);
}

}  // namespace

TimerEventReach::TimerEventReach(avr_t* avr, const McuDescription& mcu, const BoardDescription& board,
                                 const void* timer)
    : avr_(avr), timer_(timer) {
    const avr_timer_t& t = timer_of(timer);
    for (std::size_t c = 0; c < kUnits; ++c) {
        const avr_regbit_t& pin = t.comp[c].com_pin;
        if (pin.reg == 0) continue;
        for (const PortRegisters& p : mcu.ports) {
            if (p.port_register != pin.reg) continue;
            const std::optional<int> number = pin_number_of(board, PortBit{p.port, static_cast<uint8_t>(pin.bit)});
            const std::optional<PinInfo> info = number ? board_pin(board, *number) : std::nullopt;
            if (info) oc_[c] = OcPin{PinEdgeReach(avr, mcu, *info), p.pin, p.port_register, p.ddr};
        }
    }
}

bool TimerEventReach::replayable(Cycles when, const LoopSpan& span) const {
    const avr_timer_t& t = timer_of(timer_);
    // Which callback: the overflow's is due tov_cycles after the last
    // overflow, unit x's comp_cycles after it (units with equal OCRs: any of
    // them). A timer clocked from outside (Tn, AS2) has no cycle timers
    // unless given a virtual clock, which the HIL never does.
    const Cycles since = when - t.tov_base;
    if (t.tov_cycles > 1 && since == t.tov_cycles) return overflow_replayable(span);
    bool unit_found = false;
    for (std::size_t c = 0; c < kUnits; ++c) {
        const avr_timer_comp_t& u = t.comp[c];
        if (u.r_ocr == 0 || u.comp_cycles == 0 || u.comp_cycles == t.tov_cycles || since != u.comp_cycles) continue;
        unit_found = true;
        if (!compare_replayable(c, span)) return false;
    }
    return unit_found;  // else not a callback known here: it bounds the jump
}

bool TimerEventReach::overflow_replayable(const LoopSpan& span) const {
    const avr_timer_t& t = timer_of(timer_);
    // An enable bit set and cleared again within a pass (TIMSKn is a plain
    // register) would let a raise request an interrupt there.
    if (span.writes(t.overflow.enable.reg)) return false;
    // It moves the count's base (TCNTn reads follow it) and sets TOVn.
    if (span.reads(t.r_tcnt) || (t.r_tcnth != 0 && span.reads(t.r_tcnth)) || flag_read(t.overflow.raised, span)) {
        return false;
    }
    if (enabled(avr_, t.overflow.enable)) return false;
    for (std::size_t c = 0; c < kUnits; ++c) {
        const avr_timer_comp_t& u = t.comp[c];
        if (u.r_ocr == 0 || u.comp_cycles == 0) continue;
        // A unit at TOP runs from here; the others' OC outputs go to their
        // BOTTOM level, and their callbacks are armed (run in the jump's replay too).
        if (!compare_replayable(c, span)) return false;
    }
    return true;
}

bool TimerEventReach::compare_replayable(std::size_t unit, const LoopSpan& span) const {
    const avr_timer_comp_t& u = timer_of(timer_).comp[unit];
    if (u.r_ocr == 0) return true;
    return !enabled(avr_, u.interrupt.enable) && !span.writes(u.interrupt.enable.reg) &&
           !flag_read(u.interrupt.raised, span) && oc_edges_replayable(unit, span);
}

bool TimerEventReach::oc_edges_replayable(std::size_t unit, const LoopSpan& span) const {
    const unsigned mode = field(avr_, timer_of(timer_).comp[unit].com);
    if (mode == avr_timer_com_normal) return true;  // disconnected: nothing raised
    const std::optional<OcPin>& pin = oc_[unit];
    if (mode == avr_timer_com_toggle || !pin) return false;
    if (span.reads(pin->pin_register) || span.writes(pin->port_register) || span.writes(pin->ddr_register)) {
        return false;
    }
    return pin->reach.replayable(avr_, span, false) && pin->reach.replayable(avr_, span, true);
}

}  // namespace ddmr::hil
