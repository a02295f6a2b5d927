#pragma once
// LoopProfiler: the firmware's control-loop iterations in exact cycles, from
// the ELF's symbols alone: an iteration ends when the loop's delay() call
// (the "loop mark" function) returns. For each iteration:
//   compute = from the previous mark's return to this mark's entry
//             (the control law, PWM writes, EEPROM log writes, ...)
//   wait    = from this mark's entry to its return (delay(9))
//   period  = compute + wait
// The first call of the mark after the profiler is armed only opens the
// first iteration (its compute has no start).
//
// It watches every instruction (AvrCore's instruction hook: exact, slower):
// entry is the first instruction of the mark; the return is the first
// instruction outside it with SP back above the SP at entry (interrupts and
// callees push below it). It reads only the PC, SP and cycle
// (HookReads::kPcSpCycle): fast-forward shows it the passes it skips.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"

namespace ddmr::hil {

struct LoopIteration {
    Cycles start = 0;        ///< previous mark's return
    Cycles mark_entry = 0;   ///< first instruction of the mark
    Cycles end = 0;          ///< the mark's return
    bool eeprom_write = false;  ///< an EEPROM write started during compute
    Cycles compute() const { return mark_entry - start; }
    Cycles wait() const { return end - mark_entry; }
    Cycles period() const { return end - start; }
};

struct CycleDistribution {
    uint64_t count = 0;
    Cycles min = 0, max = 0, p99 = 0;
    double mean = 0.0;
    /// Histogram: `bins` counts of width `bin_width` from `bin_start`.
    Cycles bin_start = 0, bin_width = 1;
    std::vector<uint64_t> bins;
};

/// min/mean/p99/max of `values` and a histogram of `bin_count` equal bins.
CycleDistribution cycle_distribution(std::vector<Cycles> values, std::size_t bin_count = 20);

class LoopProfiler {
public:
    /// Installs itself as `core`'s instruction hook. `mark` must be a function.
    LoopProfiler(AvrCore& core, const ElfSymbol& mark);
    ~LoopProfiler();
    LoopProfiler(const LoopProfiler&) = delete;
    LoopProfiler& operator=(const LoopProfiler&) = delete;

    /// Starts counting iterations from the next return of the mark (earlier
    /// calls, such as setup()'s delay(5000), are not iterations).
    void arm() { armed_ = true; }

    /// Called at every return of the mark once armed, right after the
    /// iteration is recorded: `completed` is false for the first return
    /// (it only opens the first iteration) and true whenever an iteration
    /// ends (then iterations().back() is the one that ended, and the next
    /// one starts at the same cycle). Lets other profilers split their
    /// counts at exactly the same boundaries.
    void set_iteration_listener(std::function<void(bool completed)> listener) {
        listener_ = std::move(listener);
    }

    const std::vector<LoopIteration>& iterations() const { return iterations_; }
    /// Marks the iterations whose compute part contains one of these cycles.
    void tag_eeprom_writes(const std::vector<Cycles>& write_cycles);

private:
    void on_instruction();

    AvrCore& core_;
    uint32_t begin_ = 0, end_ = 0;
    bool armed_ = false;
    bool inside_ = false;
    uint16_t sp_at_entry_ = 0;
    Cycles entry_cycle_ = 0;
    bool have_start_ = false;
    Cycles start_cycle_ = 0;
    std::vector<LoopIteration> iterations_;
    std::function<void(bool)> listener_;
    /// Entries into and returns from the mark: on_instruction decides from
    /// the PC, the SP and inside_ alone, and reads the cycle only at these
    /// (AvrCore::add_instruction_hook's state_changes).
    uint64_t state_changes_ = 0;
};

}  // namespace ddmr::hil
