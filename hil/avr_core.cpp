#include "hil/avr_core.hpp"

#include <algorithm>
#include <type_traits>

#include <avr_extint.h>
#include <avr_uart.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include <sim_elf.h>
#include <sim_io.h>
#include <sim_irq.h>

#include <fmt/format.h>

#include <cstdlib>
#include <cstring>
#include <new>
#include <stdexcept>
#include <string>

namespace ddmr::hil {
namespace {

/// simavr's default sleep callback usleep()s to keep pace with the wall clock;
/// the HIL runs as fast as it can, so sleeping does nothing.
void no_wall_clock_sleep(avr_t* /*avr*/, avr_cycle_count_t /*how_long*/) {}

/// Frees what elf_read_firmware allocated (simavr 1.6 has no function for it).
struct FirmwareBuffers {
    elf_firmware_t fw{};
    ~FirmwareBuffers() {
        std::free(fw.flash);
        std::free(fw.eeprom);
        std::free(fw.fuse);
        std::free(fw.lockbits);
        for (uint32_t i = 0; i < fw.symbolcount; ++i) std::free(fw.symbol[i]);
        std::free(fw.symbol);
    }
};

/// Reads `elf` with simavr's own loader and checks that avr_load_firmware()
/// can take it: simavr's avr_loadcode() abort()s on a program that does not
/// fit, and ElfImage checks the sections while the loader's own layout
/// decides (found by tests/fuzz/elf_loader_fuzz.cpp on a damaged section table).
void read_loadable(const ElfImage& elf, const McuDescription& mcu, FirmwareBuffers& buffers) {
    const std::string path = elf.path().string();
    if (elf_read_firmware(path.c_str(), &buffers.fw) != 0) {
        throw std::runtime_error("firmware " + path + ": simavr's ELF loader could not read it");
    }
    const uint64_t end = static_cast<uint64_t>(buffers.fw.flashbase) + buffers.fw.flashsize;
    if (end > mcu.flash_bytes) {
        throw std::runtime_error(fmt::format(
            "firmware {}: simavr's ELF loader places {} bytes of program at 0x{:04x}, past the "
            "{}'s {}-byte flash",
            path, buffers.fw.flashsize, buffers.fw.flashbase, mcu.label, mcu.flash_bytes));
    }
}

struct TargetFlag {
    bool reached = false;
};

avr_cycle_count_t on_target(avr_t* /*avr*/, avr_cycle_count_t /*when*/, void* param) {
    static_cast<TargetFlag*>(param)->reached = true;
    return 0;
}

avr_cycle_count_t on_stop_deadline(avr_t* /*avr*/, avr_cycle_count_t /*when*/, void* param) {
    static_cast<AvrCore*>(param)->request_stop();
    return 0;
}

}  // namespace

const char* to_string(RunStop stop) {
    switch (stop) {
        case RunStop::kReachedCycle: return "reached_cycle";
        case RunStop::kCondition: return "condition";
        case RunStop::kCrashed: return "crashed";
        case RunStop::kDone: return "sleeping_with_interrupts_off";
        case RunStop::kWatchdogReset: return "watchdog_reset";
        case RunStop::kSimavrError: return "simavr_error";
    }
    return "unknown";
}

void AvrCore::AvrDeleter::operator()(avr_t* avr) const {
    avr_terminate(avr);
    // simavr 1.6's avr_terminate frees the I/O modules' IRQs but leaves every
    // other IRQ in the pool (vector and iomem IRQs: their names, notify hooks
    // and avr_alloc_irq arrays), the pool's table and the avr_t itself.
    // IRQs of one array sit in consecutive pool slots at consecutive
    // addresses; avr_free_irq(base, n) frees such an array as simavr would.
    avr_irq_pool_t& pool = avr->irq_pool;
    int i = 0;
    while (i < pool.count) {
        avr_irq_t* base = pool.irq[i];
        if (base == nullptr) {
            ++i;
            continue;
        }
        int n = 1;
        while (i + n < pool.count && pool.irq[i + n] == base + n) ++n;
        avr_free_irq(base, static_cast<uint32_t>(n));  // also clears the n pool slots
        i += n;
    }
    std::free(pool.irq);
    std::free(avr);
}

void AvrCore::check_loadable(const ElfImage& elf, const McuDescription& mcu) {
    install_simavr_logger();
    SimavrLog loader_log;  // the loader's messages: not for stderr, the core's run reports them
    const LoadingLogScope scope(&loader_log);
    FirmwareBuffers buffers;
    read_loadable(elf, mcu, buffers);
}

void AvrCore::widen_data_space(avr_t* avr) {
    // simavr 1.6 allocates ramend + 1 bytes of data space, but a push or pop
    // through a wild stack pointer (SP up to 0xFFFF: a firmware that crashed)
    // indexes avr->data[SP] without a bound check (_avr_push_addr ->
    // avr_core_watch_write), i.e. up to 62 KiB past simavr's heap block:
    // silent heap corruption in a normal build, SIGSEGV under ASan (found by
    // tests/fuzz/elf_loader_fuzz.cpp). Give it the whole 16-bit space; the
    // bytes past RAMEND are never read as RAM by a sane firmware, and the
    // run is reported as crashed (stack_guard.hpp, simavr's own checks).
    constexpr std::size_t kDataSpace = 0x10000;
    auto* data = static_cast<uint8_t*>(std::calloc(kDataSpace, 1));
    if (data == nullptr) throw std::bad_alloc();
    std::memcpy(data, avr->data, static_cast<std::size_t>(avr->ramend) + 1);
    std::free(avr->data);  // avr_terminate frees the new block the same way
    avr->data = data;
}

AvrCore::AvrCore(const ElfImage& elf, const AvrCoreConfig& config)
    : elf_(elf),
      config_(config),
      board_(board_description(config.board)),
      spl_(board_.mcu->spl),
      sph_(board_.mcu->sph) {
    if (config_.run_cycle_limit == 0) {
        throw std::invalid_argument("AvrCore: run_cycle_limit must be >= 1");
    }
    install_simavr_logger();
    const LoadingLogScope scope(&log_);

    const McuDescription& chip = mcu();
    avr_.reset(avr_make_mcu_by_name(chip.name));
    if (!avr_) throw std::runtime_error(fmt::format("simavr has no {} core", chip.label));
    avr_t* avr = avr_.get();
    avr->custom.data = &log_;  // routes this instance's log (see simavr_log.cpp)
    if (avr_init(avr) != 0) throw std::runtime_error(fmt::format("simavr could not initialise the {}", chip.label));
    widen_data_space(avr);
    static_assert(std::is_same_v<decltype(avr->cycle), avr_cycle_count_t> && sizeof(avr_cycle_count_t) == 8);
    static_assert(std::is_same_v<decltype(avr->pc), avr_flashaddr_t> && sizeof(avr_flashaddr_t) == 4);
    cycle_ = &avr->cycle;
    pc_ = &avr->pc;
    data_ = avr->data;

    FirmwareBuffers buffers;
    read_loadable(elf_, chip, buffers);
    const std::string path = elf_.path().string();
    buffers.fw.frequency = clock_hz();
    std::snprintf(buffers.fw.mmcu, sizeof buffers.fw.mmcu, "%s", chip.name);
    avr_load_firmware(avr, &buffers.fw);
    avr->frequency = clock_hz();
    avr->log = SimavrLog::kLevelWarning;

    apply_setup();
    pin_change_ = std::make_unique<PinChangeRestorer>(avr, chip);
    normal_run_ = avr->run;
}

bool AvrCore::event_pending() const {
    return avr_->run != normal_run_ || log_.hard_errors() != hard_errors_seen_;
}

RunStop AvrCore::take_event() {
    if (avr_->run != normal_run_) {
        // simavr's watchdog replaced the run callback by one that resets: do
        // the reset here, with the parts re-armed, and flag it as the chip does.
        avr_->run = normal_run_;
        reset();
        avr_->data[mcu().mcusr] |= atmega328p::kWdrf;
        ++watchdog_resets_;
        return RunStop::kWatchdogReset;
    }
    hard_errors_seen_ = log_.hard_errors();
    // A crash is logged as an error too: report it as the crash it is.
    if (avr_->state == cpu_Crashed) return RunStop::kCrashed;
    return RunStop::kSimavrError;
}

void AvrCore::apply_setup() {
    avr_t* avr = avr_.get();
    uint32_t uart_flags = 0;  // no stdio echo, no poll-sleep
    for (const UsartDesc& u : mcu().usarts) {
        avr_ioctl(avr, AVR_IOCTL_UART_SET_FLAGS(static_cast<char>('0' + u.index)), &uart_flags);
    }
    avr->sleep = &no_wall_clock_sleep;
    for (std::size_t n = 0; n < mcu().ext_int_pins.size(); ++n) avr_extint_set_strict_lvl_trig(avr, static_cast<uint8_t>(n), 0);
    avr->run_cycle_limit = free_run_limit();
}

void AvrCore::reset() {
    avr_t* avr = avr_.get();
    const Cycles now = avr->cycle;
    avr_reset(avr);
    avr->cycle = now;  // time goes on (simavr 1.6 keeps it too; this makes it explicit)
    stop_requested_ = false;
    apply_setup();
    ++resets_;
    for (const auto& l : reset_listeners_) l.hook();
}

namespace {

/// Replaces the entry of `entry.owner` in `list` in its place (the order
/// stays), or appends it.
template <typename Entry>
void set_owned(std::vector<Entry>& list, Entry entry) {
    for (auto& e : list) {
        if (e.owner == entry.owner) {
            e = std::move(entry);
            return;
        }
    }
    list.push_back(std::move(entry));
}

template <typename Entry>
void erase_owned(std::vector<Entry>& list, const void* owner) {
    list.erase(std::remove_if(list.begin(), list.end(), [owner](const Entry& e) { return e.owner == owner; }),
               list.end());
}

}  // namespace

void AvrCore::add_instruction_hook(const void* owner, std::function<void()> hook, HookReads reads,
                                   std::function<uint64_t()> state_changes) {
    set_owned(instruction_hooks_, InstructionHook{owner, std::move(hook), std::move(state_changes)});
    opaque_hooks_.erase(std::remove(opaque_hooks_.begin(), opaque_hooks_.end(), owner), opaque_hooks_.end());
    if (reads == HookReads::kAnything) opaque_hooks_.push_back(owner);
}
void AvrCore::remove_instruction_hook(const void* owner) {
    erase_owned(instruction_hooks_, owner);
    opaque_hooks_.erase(std::remove(opaque_hooks_.begin(), opaque_hooks_.end(), owner), opaque_hooks_.end());
}
void AvrCore::add_reset_listener(const void* owner, std::function<void()> fn) {
    set_owned(reset_listeners_, OwnedCallback{owner, std::move(fn)});
}
void AvrCore::remove_reset_listener(const void* owner) { erase_owned(reset_listeners_, owner); }

AvrCore::~AvrCore() = default;

uint32_t AvrCore::return_address_at(uint32_t first) const {
    uint32_t word = 0;
    for (uint32_t i = 0; i < mcu().pc_bytes; ++i) word = (word << 8) | avr_->data[(first + i) & 0xFFFFU];
    return word * 2;
}

uint8_t AvrCore::data(uint16_t address) const {
    if (address > avr_->ramend) {
        throw std::out_of_range("AVR data address " + std::to_string(address) + " past RAMEND");
    }
    return avr_->data[address];
}

void AvrCore::set_sram(uint16_t address, uint8_t value) {
    if (address < mcu().sram_start || address > avr_->ramend) {
        throw std::out_of_range("AVR data address " + std::to_string(address) + " is not in SRAM");
    }
    avr_->data[address] = value;
}

RunStop AvrCore::state_stop() const {
    if (avr_->state == cpu_Crashed) return RunStop::kCrashed;
    if (avr_->state == cpu_Done) return RunStop::kDone;
    return RunStop::kReachedCycle;
}

RunStop AvrCore::run_until(Cycles target) {
    avr_t* avr = avr_.get();
    if (avr->cycle >= target) return state_stop();
    if (stop_requested_) return RunStop::kCondition;
    TargetFlag flag;
    avr_cycle_timer_register(avr, target - avr->cycle, &on_target, &flag);
    // Lets fast-forward look at the batch end; true if the run must stop
    // for an event it stopped stepping for.
    const auto look = [this, &flag] {
        if (!fast_forward_->after_batch(flag.reached, stop_requested_)) return false;
        if (step_watch_ != nullptr) step_watch_(step_watch_context_);  // an interrupt it stepped into switched the watch on
        return event_pending();
    };
    if (!instruction_hooks_.empty()) {
        avr->run_cycle_limit = 1;  // one instruction per avr_run
        avr->run_cycle_count = 1;
        stepping_ = true;
        // Fast-forward looks for loops at the PCs reached every
        // kSamplePeriod cycles, as where free-running batches end.
        const bool skips = fast_forward_ && hooks_replayable();
        Cycles next_look = avr->cycle + FastForward::kSamplePeriod;
        while (!flag.reached && !stop_requested_) {
            const int state = avr_run(avr);
            run_instruction_hooks();
            if (step_watch_ != nullptr) step_watch_(step_watch_context_);
            if (state == cpu_Crashed || state == cpu_Done || event_pending()) break;
            if (!skips || step_watch_ != nullptr || avr->cycle < next_look) continue;
            next_look = avr->cycle + FastForward::kSamplePeriod;
            if (look()) break;
        }
        stepping_ = false;
        avr->run_cycle_limit = free_run_limit();
    } else {
        while (!flag.reached && !stop_requested_) {
            const int state = avr_run(avr);
            if (step_watch_ != nullptr) step_watch_(step_watch_context_);  // the next instruction, on every path
            if (state == cpu_Crashed || state == cpu_Done || event_pending()) break;
            if (fast_forward_ && step_watch_ == nullptr && look()) break;
        }
    }
    avr_cycle_timer_cancel(avr, &on_target, &flag);
    if (event_pending()) return take_event();
    const RunStop stop = state_stop();
    if (stop == RunStop::kReachedCycle && stop_requested_) return RunStop::kCondition;
    return stop;
}

void AvrCore::set_fast_forward(bool on) {
    if (!on) {
        fast_forward_.reset();
    } else if (!fast_forward_) {
        fast_forward_ = std::make_unique<FastForward>(*this, replayable_, io_watchers_);
    }
    avr_.get()->run_cycle_limit = free_run_limit();
}

avr_irq_t* AvrCore::watch_io(uint16_t address, void (*notify)(avr_irq_t*, uint32_t, void*), void* param,
                             IoReads reads) {
    avr_irq_t* irq = avr_iomem_getirq(avr_.get(), address, nullptr, AVR_IOMEM_IRQ_ALL);
    if (irq == nullptr) throw std::runtime_error(fmt::format("simavr has no IRQ for I/O register 0x{:02x}", address));
    avr_irq_register_notify(irq, notify, param);
    IoWatchers& w = io_watchers_[address];
    ++w.count;
    if (reads == IoReads::kMatter) ++w.reads_matter;
    return irq;
}

void AvrCore::unwatch_io(uint16_t address, void (*notify)(avr_irq_t*, uint32_t, void*), void* param, IoReads reads) {
    avr_irq_t* irq = avr_iomem_getirq(avr_.get(), address, nullptr, AVR_IOMEM_IRQ_ALL);
    if (irq != nullptr) avr_irq_unregister_notify(irq, notify, param);
    IoWatchers& w = io_watchers_[address];
    --w.count;
    if (reads == IoReads::kMatter) --w.reads_matter;
}

void AvrCore::forget_replay(const void* param) {
    replayable_.erase(std::remove_if(replayable_.begin(), replayable_.end(),
                                     [param](const ReplayableTimer& r) { return r.param == param; }),
                      replayable_.end());
}

Cycles AvrCore::free_run_limit() const {
    if (step_watch_ != nullptr || stepping_) return 1;
    // Fast-forward finds loops by the PCs batches end at: end one at least
    // every kSamplePeriod cycles (at cycle timers alone they can be far apart).
    return fast_forward_ ? std::min(config_.run_cycle_limit, FastForward::kSamplePeriod) : config_.run_cycle_limit;
}

void AvrCore::set_step_watch(StepWatch watch, void* context) {
    step_watch_ = watch;
    step_watch_context_ = context;
    avr_t* avr = avr_.get();
    if (watch != nullptr) {
        avr->run_cycle_limit = 1;
        avr->run_cycle_count = 1;  // the batch in progress ends after this instruction
    } else if (!stepping_) {
        avr->run_cycle_limit = free_run_limit();
    }
}

void AvrCore::request_stop() {
    stop_requested_ = true;
    avr_->run_cycle_count = 1;  // simavr's batch ends after the instruction in progress
}

void AvrCore::stop_after(Cycles delay) {
    avr_cycle_timer_register(avr_.get(), delay == 0 ? 1 : delay, &on_stop_deadline, this);
}

RunStop AvrCore::run_until(Cycles target, const std::function<bool()>& condition) {
    avr_t* avr = avr_.get();
    avr->run_cycle_limit = 1;  // one instruction per avr_run
    avr->run_cycle_count = 1;
    stepping_ = true;
    RunStop stop = RunStop::kReachedCycle;
    while (avr->cycle < target) {
        const int state = avr_run(avr);
        if (step_watch_ != nullptr) step_watch_(step_watch_context_);
        if (state == cpu_Crashed || state == cpu_Done) {
            stop = state_stop();
            break;
        }
        if (event_pending()) {
            stepping_ = false;
            avr->run_cycle_limit = free_run_limit();
            return take_event();
        }
        if (condition()) {
            stop = RunStop::kCondition;
            break;
        }
    }
    stepping_ = false;
    avr->run_cycle_limit = free_run_limit();
    return stop;
}

namespace {

struct ReturnWatch {
    AvrCore* core = nullptr;
    uint32_t begin = 0;  ///< flash byte address of the function
    uint32_t end = 0;    ///< one past its last byte
    bool entered = false;
    uint16_t sp_before_call = 0;  ///< SP the caller had before its CALL
};

/// True if the instruction just before flash byte address `ret_byte` is a
/// CALL (4 bytes) or RCALL (2 bytes) to the function at `target_byte`.
bool follows_call_to(const AvrCore& core, uint32_t ret_byte, uint32_t target_byte) {
    if (ret_byte >= 4) {
        const uint16_t w0 = core.flash_word(ret_byte - 4);
        if ((w0 & 0xFE0E) == 0x940E) {  // CALL k: 1001 010k kkkk 111k, kkkk kkkk kkkk kkkk
            const uint32_t k = ((static_cast<uint32_t>(w0 & 0x01F0) >> 3) |
                                static_cast<uint32_t>(w0 & 0x0001)) << 16 |
                               core.flash_word(ret_byte - 2);
            if (k * 2 == target_byte) return true;
        }
    }
    if (ret_byte >= 2) {
        const uint16_t w = core.flash_word(ret_byte - 2);
        if ((w & 0xF000) == 0xD000) {  // RCALL k: 1101 kkkk kkkk kkkk, k signed words
            int64_t k = w & 0x0FFF;
            if (k & 0x0800) k -= 0x1000;
            if (static_cast<int64_t>(ret_byte) + 2 * k == target_byte) return true;
        }
    }
    return false;
}

avr_cycle_count_t on_return_sample(avr_t* /*avr*/, avr_cycle_count_t when, void* param) {
    auto* w = static_cast<ReturnWatch*>(param);
    const AvrCore& core = *w->core;
    const uint16_t sp = core.stack_pointer();
    if (!w->entered) {
        // In a timer callback simavr's PC is that of the last instruction run.
        const uint32_t pc = core.pc();
        if (pc < w->begin || pc >= w->end) return when + AvrCore::kReturnSamplePeriod;
        // CALL pushed the return word address, high byte first, at SP+1
        // (as seen after the push). Find the lowest such slot above SP.
        const uint32_t last = core.mcu().pc_bytes - 1U;
        for (uint32_t a = sp + 1U; a + last <= core.mcu().ram_end; ++a) {
            if (follows_call_to(core, core.return_address_at(a), w->begin)) {
                w->entered = true;
                w->sp_before_call = static_cast<uint16_t>(a + last);
                break;
            }
        }
    } else if (sp >= w->sp_before_call) {
        w->core->request_stop();
        return 0;
    }
    return when + AvrCore::kReturnSamplePeriod;
}

}  // namespace

uint16_t AvrCore::flash_word(uint32_t byte_address) const {
    if (byte_address + 1 > avr_->flashend) return 0xFFFF;
    return static_cast<uint16_t>(avr_->flash[byte_address] | (avr_->flash[byte_address + 1] << 8));
}

RunStop AvrCore::run_until_return_from(const ElfSymbol& function, Cycles target) {
    if (!function.is_function || function.size == 0) {
        throw std::invalid_argument("run_until_return_from: '" + function.name +
                                    "' is not a function with a size in the ELF");
    }
    ReturnWatch watch{this, function.address, function.address + function.size, false, 0};
    avr_cycle_timer_register(avr_.get(), kReturnSamplePeriod, &on_return_sample, &watch);
    // Replayable over passes that cannot make a sample act: once the call is
    // found, passes whose SP stays below its slot; before, passes outside the function.
    allow_replay({&on_return_sample, &watch, [&watch](const LoopSpan& s) {
                      if (watch.entered) return s.max_sp < watch.sp_before_call;
                      return std::none_of(s.pcs->begin(), s.pcs->end(),
                                          [&watch](uint32_t pc) { return pc >= watch.begin && pc < watch.end; });
                  }});
    const RunStop stop = run_until(target);
    forget_replay(&watch);
    avr_cycle_timer_cancel(avr_.get(), &on_return_sample, &watch);
    stop_requested_ = false;
    return stop;
}

}  // namespace ddmr::hil
