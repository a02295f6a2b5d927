#include "hil/eeprom_write_timing.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <algorithm>
#include <stdexcept>
#include <type_traits>

namespace ddmr::hil {
namespace {

static_assert(std::is_same_v<avr_cycle_count_t, uint64_t>,
              "on_write_done is declared with uint64_t for simavr's avr_cycle_count_t");

constexpr uint8_t bit_mask(int bit) { return static_cast<uint8_t>(1U << bit); }
constexpr uint8_t kEepe = bit_mask(atmega328p::eecr_bit::kEepe);
constexpr uint8_t kEempe = bit_mask(atmega328p::eecr_bit::kEempe);

}  // namespace

EepromWriteTiming::EepromWriteTiming(AvrCore& core, EepromTimingMode mode)
    : core_(core),
      mode_(mode),
      write_cycles_(mode == EepromTimingMode::kDatasheet ? eeprom_write_cycles(core.clock_hz()) : 0),
      eecr_(core.mcu().eecr),
      eear_mask_(static_cast<uint16_t>(core.mcu().eeprom_bytes - 1)),
      latest_(core.mcu().eeprom_bytes),
      written_(core.mcu().eeprom_bytes, 0) {
    const uint32_t bytes = core.mcu().eeprom_bytes;
    if (bytes == 0 || (bytes & (bytes - 1)) != 0) throw std::logic_error("EepromWriteTiming: EEPROM size not a power of two");
    writes_.reserve(kReservedWrites);
    // A read of EECR (eeprom_busy_wait's poll of EEPE) changes nothing here:
    // it starts no write (a read's value is EECR itself, so "EEMPE in the
    // value, clear in the register" never holds) and, while busy, holding
    // EEPE sets a bit already set. So fast-forward may skip the poll.
    eecr_irq_ = core_.watch_io(eecr_, &EepromWriteTiming::on_eecr, this, AvrCore::IoReads::kIgnored);
    // A reset clears EECR and cancels the completion timer: the write in
    // progress (already in simavr's EEPROM) ends there.
    core_.add_reset_listener(this, [this] { busy_ = false; });
}

EepromWriteTiming::~EepromWriteTiming() {
    core_.remove_reset_listener(this);
    core_.unwatch_io(eecr_, &EepromWriteTiming::on_eecr, this, AvrCore::IoReads::kIgnored);
    avr_cycle_timer_cancel(core_.raw(), &EepromWriteTiming::on_write_done, this);
    if (busy_) release_eepe();
}

void EepromWriteTiming::on_eecr(avr_irq_t* /*irq*/, uint32_t value, void* param) {
    auto* self = static_cast<EepromWriteTiming*>(param);
    const auto written = static_cast<uint8_t>(value);
    const uint8_t now = self->core_.raw()->data[self->eecr_];
    if ((written & (kEempe | kEepe)) == (kEempe | kEepe) && (now & kEempe) == 0) {
        self->start_write();
    } else if (self->busy_) {
        // simavr clears EEPE at the end of every EECR write (an EERE read, an
        // EEMPE arming): while programming, the chip keeps it set.
        self->hold_eepe();
    }
}

void EepromWriteTiming::start_write() {
    const avr_t* avr = core_.raw();
    const Cycles now = avr->cycle;
    EepromWrite w;
    w.cycle = now;
    const McuDescription& mcu = core_.mcu();
    w.address = static_cast<uint16_t>((avr->data[mcu.eearl] | (avr->data[mcu.eearh] << 8)) & eear_mask_);
    w.value = avr->data[mcu.eedr];
    ++write_count_;
    if (writes_.size() < kMaxRecordedWrites) writes_.push_back(w);  // reserve, or amortised growth
    latest_[w.address] = w;
    written_[w.address] = 1;

    if (mode_ == EepromTimingMode::kDatasheet) {
        if (busy_) {
            // Restarted before the previous write completed: count its time so far.
            busy_cycles_total_ += now - busy_since_;
            avr_cycle_timer_cancel(core_.raw(), &EepromWriteTiming::on_write_done, this);
        }
        busy_ = true;
        busy_since_ = now;
        hold_eepe();
        avr_cycle_timer_register(core_.raw(), write_cycles_, &EepromWriteTiming::on_write_done, this);
    }
    if (listener_) listener_(w);
}

std::vector<EepromWrite> EepromWriteTiming::latest_writes() const {
    std::vector<EepromWrite> out;
    for (std::size_t a = 0; a < latest_.size(); ++a) {
        if (written_[a] != 0) out.push_back(latest_[a]);
    }
    std::stable_sort(out.begin(), out.end(),
                     [](const EepromWrite& x, const EepromWrite& y) { return x.cycle < y.cycle; });
    return out;
}

uint64_t EepromWriteTiming::on_write_done(avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<EepromWriteTiming*>(param);
    self->busy_cycles_total_ += when - self->busy_since_;
    self->busy_ = false;
    self->release_eepe();
    return 0;  // one-shot
}

void EepromWriteTiming::hold_eepe() { core_.raw()->data[eecr_] |= kEepe; }

void EepromWriteTiming::release_eepe() {
    uint8_t& eecr = core_.raw()->data[eecr_];
    eecr = static_cast<uint8_t>(eecr & ~kEepe);
}

}  // namespace ddmr::hil
