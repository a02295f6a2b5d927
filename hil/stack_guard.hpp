#pragma once
// StackGuard: stops the run when the firmware's stack grows down into its
// static data (.data + .bss), the silent corruption of an AVR with 2 KiB of
// SRAM (issue 9: "stack overflow into .bss at cycle N").
//
// The stack pointer is sampled every `period` cycles by a cycle timer (the
// run stays batched and fast); SP below the end of .bss means the next push
// writes into a global. The reported cycle is the sample's, at most `period`
// cycles after the first write into .bss; a deeper excursion that returns
// between two samples is not seen. Re-armed after an AVR reset.

#include <cstdint>
#include <optional>

#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"

namespace ddmr::hil {

struct StackOverflow {
    Cycles cycle = 0;        ///< the sample that saw it
    uint16_t sp = 0;         ///< SP then
    uint16_t bss_end = 0;    ///< first address after .bss
};

class StackGuard {
public:
    static constexpr Cycles kDefaultPeriod = 1024;
    /// Watches SP against the end of `elf`'s .bss (0x100 + .data + .bss).
    StackGuard(AvrCore& core, const ElfImage& elf, Cycles period = kDefaultPeriod);
    ~StackGuard();
    StackGuard(const StackGuard&) = delete;
    StackGuard& operator=(const StackGuard&) = delete;

    const std::optional<StackOverflow>& overflow() const { return overflow_; }
    uint16_t bss_end() const { return bss_end_; }

private:
    static uint64_t on_sample(struct avr_t* avr, uint64_t when, void* param);
    AvrCore& core_;
    Cycles period_;
    uint16_t bss_end_;
    std::optional<StackOverflow> overflow_;
};

}  // namespace ddmr::hil
