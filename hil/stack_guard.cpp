#include "hil/stack_guard.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <stdexcept>


namespace ddmr::hil {

StackGuard::StackGuard(AvrCore& core, const ElfImage& elf, Cycles period)
    : core_(core),
      period_(period),
      bss_end_(static_cast<uint16_t>(core.mcu().sram_start + elf.memory_use().ram_bytes())) {
    if (period_ == 0) throw std::invalid_argument("StackGuard: period must be >= 1 cycle");
    avr_cycle_timer_register(core_.raw(), period_, &StackGuard::on_sample, this);
    // Over skipped passes whose SP stays above .bss, no sample would stop the run.
    core_.allow_replay({&StackGuard::on_sample, this, [this](const LoopSpan& s) { return s.min_sp >= bss_end_; }});
    core_.add_reset_listener(this, [this] {
        if (!overflow_) avr_cycle_timer_register(core_.raw(), period_, &StackGuard::on_sample, this);
    });
}

StackGuard::~StackGuard() {
    core_.remove_reset_listener(this);
    core_.forget_replay(this);
    avr_cycle_timer_cancel(core_.raw(), &StackGuard::on_sample, this);
}

uint64_t StackGuard::on_sample(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<StackGuard*>(param);
    const uint16_t sp = self->core_.stack_pointer();
    if (sp < self->bss_end_) {
        self->overflow_ = StackOverflow{when, sp, self->bss_end_};
        self->core_.request_stop();
        return 0;
    }
    return when + self->period_;
}

}  // namespace ddmr::hil
