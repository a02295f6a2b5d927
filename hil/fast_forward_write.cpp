#include "hil/fast_forward.hpp"

#include <avr_ioport.h>
#include <avr_timer.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <fmt/format.h>

#include <optional>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/fast_forward_loop.hpp"
#include "hil/io_register_name.hpp"
#include "hil/mcu.hpp"

// Idempotent I/O writes (hil/fast_forward.hpp): which I/O registers a
// skipped pass may write, and the check made before each such write on a
// checked pass. A pass that writes a register the value it already holds
// changes nothing, if simavr's handling of the write changes nothing either.
// In simavr 1.6 (sim/avr_ioport.c, sim/avr_timer.c, sim/avr_extint.c):
//
// - PORTx, DDRx: avr_ioport_write / avr_ioport_ddr_write store the value and
//   raise the IRQ of every pin that is an output (with its PORT bit), has an
//   external pull (its value) or a pull-up (1), changed or not. Each raise
//   sets the pin's PIN bit, raises the port's pin-change interrupt if the
//   pin's PCMSK bit is set (whatever the level was), and reaches the pin's
//   other listeners: INTn in low-level mode raises its interrupt while the
//   level is low (with the I flag set and INTFn clear); the edge-triggered listeners (INTn on edges, a timer's
//   external clock and input capture, the HIL's pin-change restorer and VCD
//   pins) compare with the level they last saw. Inert when every raised pin
//   already reads the raised level, no raised pin's PCMSK bit is set, and no
//   raised pin is a low INTn in low-level mode.
// - TCCRnA, TCCRnB: avr_timer_write reconfigures the timer only when its
//   clock select, waveform mode or AS2 change: the same value is inert.
// - OCRnx: avr_timer_write_ocr reconfigures the timer in every mode but fast
//   PWM; in fast PWM only a new value does, and it raises the timer's PWM
//   IRQs (inert while nothing listens to them).
//
// Any other register with a simavr handler or IRQ (UDRn, EECR, ADCSRA, a
// PINx toggle, ...) refuses the loop. Parts see the written register through
// AvrCore::watch_io and must all ignore a notification of its unchanged
// value (IoReads::kIgnored). The check runs before the instruction, so a
// write that would not be inert is never made on a pass that is taken back.

namespace ddmr::hil {
namespace {

/// The byte an I/O-writing instruction is about to store (OUT, ST, STD, STS,
/// SBI, CBI; AVR Instruction Set Manual), from the registers before it runs.
std::optional<uint8_t> stored_value(uint16_t w0, const uint8_t* data) {
    const uint8_t rr = data[(w0 >> 4) & 0x1F];
    if ((w0 & 0xF800) == 0xB800) return rr;  // OUT A, Rr
    if ((w0 & 0xFD00) == 0x9800) {           // CBI / SBI A, b
        const uint16_t address = static_cast<uint16_t>(0x20 + ((w0 >> 3) & 0x1F));
        const auto bit = static_cast<uint8_t>(1U << (w0 & 7U));
        return (w0 & 0x0200) != 0 ? static_cast<uint8_t>(data[address] | bit)
                                  : static_cast<uint8_t>(data[address] & ~bit);
    }
    if ((w0 & 0xFE00) == 0x9200) {  // STS, ST X/Y/Z with pre-decrement or post-increment
        switch (w0 & 0xF) {
            case 0x0: case 0x1: case 0x2: case 0x9: case 0xA: case 0xC: case 0xD: case 0xE: return rr;
            default: return std::nullopt;  // PUSH and the others write no I/O
        }
    }
    if ((w0 & 0xD200) == 0x8200) return rr;  // ST Y/Z, STD Y+q/Z+q
    return std::nullopt;
}

bool bit_of(uint8_t v, unsigned bit) { return ((v >> bit) & 1U) != 0; }

/// True for an I/O register other than SP (whose bytes the pass analysis follows).
bool io_not_sp(const McuDescription& mcu, uint16_t address) {
    return address >= 0x20 && address < mcu.sram_start && address != mcu.spl && address != mcu.sph;
}

/// The port whose PORT or DDR register is at `address`, or nullptr.
const avr_ioport_t* port_of(const std::vector<void*>& ports, uint16_t address) {
    for (void* m : ports) {
        const auto* p = static_cast<const avr_ioport_t*>(m);
        if (address == p->r_port || address == p->r_ddr) return p;
    }
    return nullptr;
}

/// The timer with an OCR register (either byte) at `address`, or nullptr.
const avr_timer_t* timer_of_compare(const std::vector<void*>& timers, uint16_t address) {
    for (void* m : timers) {
        const auto* t = static_cast<const avr_timer_t*>(m);
        for (const avr_timer_comp_t& c : t->comp) {
            if (c.r_ocr != 0 && (address == c.r_ocr || (c.r_ocrh != 0 && address == c.r_ocrh))) return t;
        }
    }
    return nullptr;
}

}  // namespace


FastForward::WriteClass FastForward::write_class(uint16_t address) const {
    const auto& io = avr_->io[AVR_DATA_TO_IO(address)];
    if (io.w.c == nullptr && io.irq == nullptr) return WriteClass::kPlain;
    if (port_of(ports_, address) != nullptr) return WriteClass::kPort;
    if (timer_of_compare(timers_, address) != nullptr) return WriteClass::kTimerCompare;
    for (const TimerDesc& t : mcu_.timers) {
        if (address == t.tccra || address == t.tccrb) return WriteClass::kTimerControl;
    }
    return WriteClass::kOther;
}

// The pins a write of the port's PORT or DDR raises (see the top), as
// avr_ioport_update_irqs computes them, each checked against what reading
// it and its listeners would change.
bool FastForward::port_write_inert(const void* port) const {
    const auto* p = static_cast<const avr_ioport_t*>(port);
    const uint8_t ddr = avr_->data[p->r_ddr];
    const uint8_t out = avr_->data[p->r_port];
    const uint8_t pin = avr_->data[p->r_pin];
    const uint8_t pcmsk = p->r_pcint != 0 ? avr_->data[p->r_pcint] : 0;
    for (unsigned i = 0; i < 8; ++i) {
        bool level = false;
        if (bit_of(ddr, i)) {
            level = bit_of(out, i);
        } else if (bit_of(p->external.pull_mask, i)) {
            level = bit_of(p->external.pull_value, i);
        } else if (bit_of(out, i)) {
            level = true;
        } else {
            continue;  // not raised
        }
        if (bit_of(pin, i) != level || bit_of(pcmsk, i)) return false;
        if (!level && low_level_interrupt_at(p->name, i)) return false;
    }
    return true;
}

// A low level raised on INTn's pin in low-level mode: simavr's extint unit
// raises INTn then if the I flag is set and INTFn is clear (the HIL turns
// the strict level trigger's 1-cycle poll off: AvrCore). INTFn is taken as
// clear while the vector is pending (conservative: not inert).
bool FastForward::low_level_interrupt_at(char port, unsigned bit) const {
    if (avr_->sreg[S_I] == 0) return false;
    for (std::size_t n = 0; n < mcu_.ext_int_pins.size(); ++n) {
        const PortBit& b = mcu_.ext_int_pins[n];
        if (b.port != port || b.bit != bit || n / 4 >= mcu_.eicr.size()) continue;
        const unsigned sense = (avr_->data[mcu_.eicr[n / 4]] >> (2 * (n % 4))) & 3U;
        const bool flag = mcu_.eifr != 0 && bit_of(avr_->data[mcu_.eifr], static_cast<unsigned>(n % 8));
        if (sense == 0 && !flag) return true;
    }
    return false;
}

// Before the instruction at `pc` runs: true if each I/O byte it writes gets
// the value it holds, and the write is inert (see the top). Plain registers
// (no simavr handler, no IRQ: SREG, GPIORn) are the loop-carried bytes'
// business, not this check's.
bool FastForward::write_inert(uint32_t pc) const {
    const uint16_t w0 = core_.flash_word(pc);
    const StepAccess a = step_access(w0, core_.flash_word(pc + 2), cpu());
    if (!a.mem_write) return true;
    for (unsigned i = 0; i < a.count; ++i) {
        const uint16_t address = a.address[i];
        if (!io_not_sp(mcu_, address)) continue;
        const WriteClass kind = write_class(address);
        if (kind == WriteClass::kPlain) continue;
        const std::optional<uint8_t> value = stored_value(w0, avr_->data);
        if (!value || *value != avr_->data[address]) return false;
        switch (kind) {
            case WriteClass::kPort:
                if (!port_write_inert(port_of(ports_, address))) return false;
                break;
            case WriteClass::kTimerCompare:
                if (!compare_write_inert(address)) return false;
                break;
            case WriteClass::kTimerControl: break;
            default: return false;
        }
    }
    return true;
}

// An OCR write of the value it holds: in fast PWM simavr leaves the timer
// as it is (and raises its PWM IRQs: inert while nothing listens). In the
// other modes it reconfigures the timer, re-arming its cycle timers: inert
// only while none is armed and none will stay armed, that is the timer is
// stopped, or clocked from the prescaler in a phase-correct mode simavr
// lacks, where PhaseCorrectTimer runs it and cancels what simavr re-arms
// within the same write (hil/phase_correct_timer.hpp).
bool FastForward::compare_write_inert(uint16_t address) const {
    const avr_timer_t* t = timer_of_compare(timers_, address);
    if (t == nullptr) return false;
    if (t->wgm_op_mode_kind == avr_timer_wgm_fast_pwm) {
        return t->io.irq[TIMER_IRQ_OUT_PWM0].hook == nullptr && t->io.irq[TIMER_IRQ_OUT_PWM1].hook == nullptr;
    }
    const bool simavrs_kind = t->wgm_op_mode_kind == avr_timer_wgm_normal || t->wgm_op_mode_kind == avr_timer_wgm_ctc ||
                              t->wgm_op_mode_kind == avr_timer_wgm_pwm || t->wgm_op_mode_kind == avr_timer_wgm_fc_pwm;
    const bool stopped = t->cs_div_value == 0;
    if (simavrs_kind && !stopped) return false;
    if ((t->ext_clock_flags & (AVR_TIMER_EXTCLK_FLAG_TN | AVR_TIMER_EXTCLK_FLAG_AS2)) != 0) return false;
    for (const avr_cycle_timer_slot_t* c = avr_->cycle_timers.timer; c != nullptr; c = c->next) {
        if (c->param == t) return false;  // simavr runs it
    }
    return true;
}

bool FastForward::writes_checked_io(const StepAccess& access) const {
    if (!access.mem_write) return false;
    for (unsigned i = 0; i < access.count; ++i) {
        if (io_not_sp(mcu_, access.address[i]) && write_class(access.address[i]) != WriteClass::kPlain) return true;
    }
    return false;
}

// At learning: the I/O registers a pass may write (their every write is
// checked by write_inert before it runs, on each checked pass).
std::string FastForward::accept_writes(const PassAnalysis& analysis) const {
    for (uint16_t a : analysis.io_writes) {
        if (a == mcu_.spl || a == mcu_.sph) continue;
        const WriteClass kind = write_class(a);
        if (kind == WriteClass::kPlain) continue;
        if (kind == WriteClass::kOther) return fmt::format("writes {}", io_register_name(mcu_, a));
        if (io_observed(a)) return fmt::format("writes {}, which a part watches", io_register_name(mcu_, a));
    }
    return {};
}


}  // namespace ddmr::hil
