#pragma once
// EepromWriteTiming: gives the firmware's EEPROM writes the ATmega328P's
// programming time, and records the writes (the first kMaxRecordedWrites in
// order, the latest per address, and their count).
//
// On the chip a write from the CPU (atomic erase + write, EEPM1:0 = 00, what
// avr-libc's eeprom_write_byte uses) runs for 26,368 cycles of the calibrated
// 8 MHz RC oscillator, typ. 3.3 ms (datasheet 7810D, 8.6.3, Table 8-2), while
// EECR.EEPE stays set; eeprom_write_byte busy-waits on EEPE *before* each write,
// so the second of two back-to-back writes waits for the first. simavr 1.6
// stores the byte and clears EEPE inside its EECR write handler: every write
// completes at once (its EE_READY interrupt is raised 3.4 ms later regardless).
//
// Modes:
//   kDatasheet  a write holds EEPE set in the data space for the programming
//               time (eeprom_write_cycles(clock): 52,736 cycles at 16 MHz),
//               then a cycle timer clears it; a firmware that polls EEPE waits
//               as on the chip. The byte is in simavr's EEPROM from the start
//               (only a read during programming could tell; avr-libc's reads
//               wait for EEPE first).
//   kInstant    simavr's own behaviour; writes are only recorded.
//
// Signals:
//   in  EECR (data 0x3F) iomem IRQ, AVR_IOMEM_IRQ_ALL. simavr raises it after
//       its own write handler with the value written, and in 1.6 also on
//       reads (SBIC/SBIS/IN) with the current register value. A write starts
//       programming iff EEMPE was set and EEPE is written to one; the handler
//       then clears EEMPE. So "value has EEMPE and EEPE, and EECR now has
//       EEMPE clear" is exactly a programming start: EECR never holds both bits
//       after a write, so no read matches, and an EEMPE-only arming write
//       leaves EEMPE set.
//   out EECR.EEPE held (kDatasheet), written straight into avr->data.
//
// A write started while one is in progress (avr-libc never does this: it polls
// EEPE first) is recorded, and the programming time restarts from it. Not
// modelled: the split erase-only / write-only modes (EEPM1:0 = 01, 10; typ.
// 1.8 ms, Table 8-1) are timed as atomic; the CPU's 2-cycle halt on a write.

#include <cstdint>
#include <functional>
#include <vector>

#include "hil/atmega328p.hpp"
#include "hil/avr_core.hpp"
#include "hil/cycle_time.hpp"

struct avr_irq_t;

namespace ddmr::hil {

/// CPU cycles of one EEPROM write at `clock_hz` (rounded to the nearest cycle):
/// kEepromWriteRcCycles of the 8 MHz calibrated RC oscillator (Table 8-2).
constexpr Cycles eeprom_write_cycles(uint32_t clock_hz) {
    return (static_cast<Cycles>(atmega328p::kEepromWriteRcCycles) * clock_hz +
            atmega328p::kCalibratedRcHz / 2) /
           atmega328p::kCalibratedRcHz;
}
/// 26,368 RC cycles = 3.296 ms = 52,736 cycles of a 16 MHz crystal (Uno, Nano).
inline constexpr Cycles kEepromWriteCycles = eeprom_write_cycles(16'000'000);
static_assert(kEepromWriteCycles == 52'736, "Table 8-2: 26,368 cycles at 8 MHz, CPU at 16 MHz");

enum class EepromTimingMode {
    kDatasheet,  ///< writes take kEepromWriteCycles with EEPE set (the chip)
    kInstant,    ///< writes complete at once (simavr 1.6)
};

/// One EEPROM byte write, as the firmware started it.
struct EepromWrite {
    Cycles cycle = 0;       ///< AVR cycle of the instruction that set EEPE (programming start)
    uint16_t address = 0;   ///< EEAR at that moment (wrapped to the 1 KiB EEPROM, as simavr does)
    uint8_t value = 0;      ///< EEDR at that moment
};

class EepromWriteTiming {
public:
    explicit EepromWriteTiming(AvrCore& core, EepromTimingMode mode = EepromTimingMode::kDatasheet);
    /// Detaches from the core; a write still in progress completes at once
    /// (EEPE cleared), so the firmware cannot hang on it.
    ~EepromWriteTiming();
    EepromWriteTiming(const EepromWriteTiming&) = delete;
    EepromWriteTiming& operator=(const EepromWriteTiming&) = delete;

    EepromTimingMode mode() const { return mode_; }
    /// Programming time of one write [cycles]: eeprom_write_cycles(core clock)
    /// in kDatasheet mode, 0 in kInstant mode.
    Cycles write_cycles() const { return write_cycles_; }

    /// The first kMaxRecordedWrites writes, in order (all of them unless
    /// write_count() says more happened).
    const std::vector<EepromWrite>& writes() const { return writes_; }
    /// Every write so far, counted.
    uint64_t write_count() const { return write_count_; }
    /// Whether writes() holds every write.
    bool all_writes_recorded() const { return write_count_ == writes_.size(); }
    /// The latest write to each address written so far, ordered by cycle
    /// (at most one per EEPROM byte; exact however many writes there were):
    /// what the EEPROM log's sample times need.
    std::vector<EepromWrite> latest_writes() const;
    /// Cycles spent programming by writes that have completed (kDatasheet:
    /// write_cycles() each, less any cut short by a restart; kInstant: 0).
    Cycles busy_cycles_total() const { return busy_cycles_total_; }
    /// A write is in progress (EEPE held).
    bool busy() const { return busy_; }

    /// Called for every write as it starts, inside the simulation (keep it
    /// short, do not throw; AvrCore::request_stop() is fine).
    void set_listener(std::function<void(const EepromWrite&)> listener) {
        listener_ = std::move(listener);
    }

    /// Writes reserved up front: four case-1 runs of the reference sketch
    /// (240 bytes each), so a run does not reallocate inside the simulation.
    static constexpr std::size_t kReservedWrites = 1024;
    /// writes() stops growing here (1 MiB): 64 times the whole EEPROM, or
    /// 3.6 min of back-to-back writes at the datasheet's 3.3 ms each. A
    /// firmware writing in a loop (with kInstant timing, a write every few
    /// cycles) would otherwise take memory without bound; write_count() and
    /// latest_writes() stay exact.
    static constexpr std::size_t kMaxRecordedWrites = 65536;

private:
    static void on_eecr(avr_irq_t* irq, uint32_t value, void* param);
    static uint64_t on_write_done(struct avr_t* avr, uint64_t when, void* param);
    void start_write();
    void hold_eepe();
    void release_eepe();

    AvrCore& core_;
    EepromTimingMode mode_;
    Cycles write_cycles_ = 0;
    avr_irq_t* eecr_irq_ = nullptr;
    bool busy_ = false;
    Cycles busy_since_ = 0;  ///< cycle the write in progress started
    Cycles busy_cycles_total_ = 0;
    std::vector<EepromWrite> writes_;
    uint64_t write_count_ = 0;
    uint16_t eecr_;  ///< EECR's address
    /// EEAR's valid bits (10 on the ATmega328P, datasheet 8.6.1): simavr
    /// wraps an address past the end the same way.
    uint16_t eear_mask_;
    // By address, on the heap (17 KiB inside the rig would spread its hot
    // members over more cache lines: --profile ran 5 % slower).
    std::vector<EepromWrite> latest_;  ///< per EEPROM byte
    std::vector<uint8_t> written_;     ///< per EEPROM byte: latest_ entry valid
    std::function<void(const EepromWrite&)> listener_;
};

}  // namespace ddmr::hil
