#include "hil/reset_monitor.hpp"

#include <sim_avr.h>
#include <sim_io.h>

#include <cstdio>
#include <stdexcept>

#include <fmt/format.h>

#include "hil/avr_decode.hpp"

namespace ddmr::hil {
namespace {

/// Instructions after the reset vector's target searched for the start-up's
/// `out SREG` (avr-libc: `clr r1` is the first, `out SREG, r1` the second).
constexpr int kStartupSearch = 8;

/// The data address an `OUT A, Rr` writes (A + 0x20), else nullopt.
std::optional<uint16_t> out_data_address(uint16_t w0) {
    if ((w0 & 0xF800) != 0xB800) return std::nullopt;  // OUT 1011 1AAr rrrr AAAA
    return static_cast<uint16_t>(0x20 + (((w0 >> 5) & 0x30) | (w0 & 0x0F)));
}

void to_stderr(const std::string& line) { std::fprintf(stderr, "ddmr-hil: warning: %s\n", line.c_str()); }

}  // namespace

ResetRate::ResetRate(Cycles window_cycles) : window_(window_cycles) {
    if (window_ == 0) throw std::invalid_argument("ResetRate: the window must be >= 1 cycle");
}

bool ResetRate::note(Cycles cycle) {
    // With the ring full, its oldest entry and this one are kMaxPerWindow + 1 restarts.
    const bool loop = count_ >= kMaxPerWindow && cycle - last_[oldest_] < window_;
    last_[oldest_] = cycle;
    oldest_ = (oldest_ + 1) % kMaxPerWindow;
    ++count_;
    return loop;
}

std::optional<uint32_t> find_startup_sreg_write(const AvrCore& core) {
    const avr::Flow vector = avr::decode_flow(core.flash_word(0), core.flash_word(2), 0);
    uint32_t pc = vector.kind == avr::Flow::Kind::kJump && vector.target ? *vector.target : 0;
    for (int i = 0; i < kStartupSearch; ++i) {
        const uint16_t w0 = core.flash_word(pc);
        if (out_data_address(w0) == core.mcu().sreg) return pc;
        pc += 2 * avr::instruction_words(w0);
    }
    return std::nullopt;
}

ResetMonitor::ResetMonitor(AvrCore& core)
    : core_(core), startup_pc_(find_startup_sreg_write(core)), rate_(core.clock_hz()), sink_(&to_stderr) {
    if (!startup_pc_) return;
    avr_register_io_write(core_.raw(), core_.mcu().sreg, &ResetMonitor::on_sreg_write, this);
    core_.add_reset_listener(this, [this] { start_expected_ = true; });
}

ResetMonitor::~ResetMonitor() {
    if (!startup_pc_) return;
    core_.remove_reset_listener(this);
    // simavr 1.6 has no unregister: clear this monitor's entry, direct or in
    // simavr's dispatcher of a register with several writers.
    avr_t* avr = core_.raw();
    auto& slot = avr->io[AVR_DATA_TO_IO(core_.mcu().sreg)].w;
    if (slot.c == &ResetMonitor::on_sreg_write && slot.param == this) {
        slot.c = nullptr;
        slot.param = nullptr;
        return;
    }
    // The dispatcher keeps its callbacks as void* (simavr 1.6's sim_avr.h).
    void* const mine = reinterpret_cast<void*>(&ResetMonitor::on_sreg_write);
    for (int n = 0; n < avr->io_shared_io_count; ++n) {
        for (int i = 0; i < avr->io_shared_io[n].used; ++i) {
            auto& entry = avr->io_shared_io[n].io[i];
            if (entry.c == mine && entry.param == this) {
                entry.c = nullptr;
                entry.param = nullptr;
            }
        }
    }
}

void ResetMonitor::on_sreg_write(avr_t* avr, uint16_t address, uint8_t value, void* param) {
    avr->data[address] = value;  // a write callback stores the value itself
    auto* self = static_cast<ResetMonitor*>(param);
    if (avr->pc == *self->startup_pc_) self->on_start();
}

void ResetMonitor::on_start() {
    if (start_expected_) {
        start_expected_ = false;
        return;
    }
    const Cycles now = core_.cycle();
    const bool loop = rate_.note(now);
    if (!first_) {
        const uint16_t sp = core_.stack_pointer();
        first_ = UnaskedReset{now, sp, origin(sp)};
        sink_(fmt::format("the firmware restarted from address 0 without a reset at cycle {} (t = {:.6f} s): {}; "
                          "restarts like it are counted (unasked_resets), more than {} within a simulated second "
                          "end the run (reset_loop)",
                          now, cycles_to_s(now, core_.clock_hz()), first_->from, ResetRate::kMaxPerWindow));
    }
    if (loop && !loop_) {
        loop_ = ResetLoop{now, rate_.count(), first_->from};
        core_.request_stop();
    }
}

std::string ResetMonitor::in_function(uint32_t pc) const {
    const auto f = core_.elf().function_at(pc);
    return f ? " in " + demangle(f->name) : std::string();
}

std::string ResetMonitor::origin(uint16_t sp) const {
    const McuDescription& mcu = core_.mcu();
    const uint16_t z = static_cast<uint16_t>(core_.data(30) | (core_.data(31) << 8));
    // A call pushed its return address at SP + 1 (high byte first).
    if (static_cast<uint32_t>(sp) + mcu.pc_bytes <= mcu.ram_end) {
        const uint32_t ret = core_.return_address_at(sp + 1U);
        if (ret >= 4) {
            const uint32_t at = ret - 4;
            const uint16_t w0 = core_.flash_word(at);
            const avr::Flow f = avr::decode_flow(w0, core_.flash_word(at + 2), at);
            if (avr::instruction_words(w0) == 2 && f.kind == avr::Flow::Kind::kCall && f.target == 0U) {
                return fmt::format("`call 0` at PC 0x{:04x}{}", at, in_function(at));
            }
        }
        if (ret >= 2) {
            const uint32_t at = ret - 2;
            const uint16_t w0 = core_.flash_word(at);
            const avr::Flow f = avr::decode_flow(w0, 0, at);
            if (f.kind == avr::Flow::Kind::kCall && f.target == 0U) {
                return fmt::format("`rcall` to 0 at PC 0x{:04x}{}", at, in_function(at));
            }
            if (f.kind == avr::Flow::Kind::kCall && !f.target && z == 0) {
                return fmt::format("`{}` with Z = 0 (a null function pointer) at PC 0x{:04x}{}",
                                   w0 == 0x9519 ? "eicall" : "icall", at, in_function(at));
            }
        }
    }
    // Not a call: a RET popped its address from just below SP, a jump left no trace.
    bool zero_below = sp >= mcu.sram_start + mcu.pc_bytes - 1U && sp <= mcu.ram_end;
    for (uint32_t i = 0; zero_below && i < mcu.pc_bytes; ++i) zero_below = core_.data(static_cast<uint16_t>(sp - i)) == 0;
    return fmt::format("a jump to address 0{} from an unknown PC (simavr keeps no previous PC; SP 0x{:04x}, Z 0x{:04x})",
                       zero_below ? ", or a return into it (a zero return address lies just below SP)" : "", sp, z);
}

}  // namespace ddmr::hil
