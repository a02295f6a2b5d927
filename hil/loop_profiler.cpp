#include "hil/loop_profiler.hpp"

#include <algorithm>
#include <stdexcept>

namespace ddmr::hil {

CycleDistribution cycle_distribution(std::vector<Cycles> values, std::size_t bin_count) {
    CycleDistribution s;
    if (values.empty()) return s;
    std::sort(values.begin(), values.end());
    s.count = values.size();
    s.min = values.front();
    s.max = values.back();
    double sum = 0.0;
    for (const Cycles v : values) sum += static_cast<double>(v);
    s.mean = sum / static_cast<double>(values.size());
    // Nearest-rank 99th percentile: the smallest value with >= 99 % at or below it.
    const std::size_t rank = (99 * values.size() + 99) / 100;
    s.p99 = values[std::max<std::size_t>(rank, 1) - 1];
    if (bin_count == 0) bin_count = 1;
    s.bin_start = s.min;
    s.bin_width = std::max<Cycles>(1, (s.max - s.min) / bin_count + 1);
    s.bins.assign(bin_count, 0);
    for (const Cycles v : values) ++s.bins[static_cast<std::size_t>((v - s.bin_start) / s.bin_width)];
    return s;
}

LoopProfiler::LoopProfiler(AvrCore& core, const ElfSymbol& mark) : core_(core) {
    if (!mark.is_function || mark.size == 0) {
        throw std::invalid_argument("loop mark '" + mark.name + "' is not a function with a size in the ELF");
    }
    begin_ = mark.address;
    end_ = mark.address + mark.size;
    iterations_.reserve(4096);
    core_.add_instruction_hook(this, [this] { on_instruction(); }, AvrCore::HookReads::kPcSpCycle,
                               [this] { return state_changes_; });
    // An iteration cut by a reset is not an iteration.
    core_.add_reset_listener(this, [this] {
        ++state_changes_;
        inside_ = false;
        have_start_ = false;
    });
}

LoopProfiler::~LoopProfiler() {
    core_.remove_instruction_hook(this);
    core_.remove_reset_listener(this);
}

void LoopProfiler::on_instruction() {
    const uint32_t pc = core_.pc();  // the next instruction to run
    if (!inside_) {
        if (pc == begin_) {  // CALL/RCALL just transferred control to the mark
            ++state_changes_;
            inside_ = true;
            sp_at_entry_ = core_.stack_pointer();
            entry_cycle_ = core_.cycle();
        }
        return;
    }
    if ((pc >= begin_ && pc < end_) || core_.stack_pointer() <= sp_at_entry_) return;
    ++state_changes_;
    inside_ = false;  // RET: back in the caller
    const Cycles now = core_.cycle();
    if (!armed_) return;
    const bool completed = have_start_;
    if (completed) iterations_.push_back(LoopIteration{start_cycle_, entry_cycle_, now, false});
    have_start_ = true;
    start_cycle_ = now;
    if (listener_) listener_(completed);
}

void LoopProfiler::tag_eeprom_writes(const std::vector<Cycles>& write_cycles) {
    for (LoopIteration& it : iterations_) {
        const auto lo = std::lower_bound(write_cycles.begin(), write_cycles.end(), it.start);
        it.eeprom_write = lo != write_cycles.end() && *lo < it.mark_entry;
    }
}

}  // namespace ddmr::hil
