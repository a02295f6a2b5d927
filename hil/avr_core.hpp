#pragma once
// AvrCore: one simavr MCU instance on one Arduino board (the board's MCU and
// clock, hil/board_description.hpp) running one firmware ELF, owned
// RAII-style (simavr 1.6's avr_terminate frees neither the avr_t nor the ELF
// loader's buffers; this class frees all of them).
//
// Set-up applied at construction (see ../shared/SIMAVR_NOTES.md):
//   - the board's clock set before the firmware is loaded (avr_init leaves 1 MHz);
//   - UART stdio and poll-sleep flags off; no wall-clock sleep callback;
//   - INT0/INT1 strict level triggering off (its 1-cycle poll costs 4x speed);
//   - pin-change groups simavr's core lacks restored (PinChangeRestorer);
//   - simavr's log routed to this instance's SimavrLog;
//   - instructions batched between cycle timers (run_cycle_limit).
//
// Signals: none of its own; parts (UartLink, EepromPort, ...) attach to raw().
// Not thread-safe: call an instance only from the thread that uses it.

#include <cstdint>
#include <functional>
#include <memory>
#include <unordered_map>
#include <vector>

#include "hil/board_description.hpp"
#include "hil/cycle_time.hpp"
#include "hil/elf_image.hpp"
#include "hil/fast_forward.hpp"
#include "hil/pin_change_restorer.hpp"
#include "hil/simavr_log.hpp"

struct avr_t;

namespace ddmr::hil {

struct AvrCoreConfig {
    /// The board: its MCU (the simavr core), its clock, its pins.
    BoardModel board = BoardModel::uno;
    /// Maximum cycles simavr executes between checks for timers and interrupts
    /// when nothing is due sooner. Any value >= 1 gives identical results; a
    /// large one is faster. simavr's own default is 1.
    Cycles run_cycle_limit = 100'000;
};

/// Why a run_until call returned.
enum class RunStop {
    kReachedCycle,  ///< the target cycle was reached
    kCondition,     ///< the caller's condition became true, or a stop was requested
    kCrashed,       ///< simavr reported cpu_Crashed (PC past flash, bad data access)
    kDone,          ///< the firmware slept with interrupts off: it can never wake
    /// The watchdog expired with WDE set: the AVR has been reset (reset(),
    /// MCUSR.WDRF set, as the chip does) and the run stops there.
    kWatchdogReset,
    /// simavr logged an error (an invalid opcode, ...): log().first_error().
    kSimavrError,
};

const char* to_string(RunStop stop);

class AvrCore {
public:
    /// Loads `elf` (already validated with ElfImage::require_mcu()) into a
    /// fresh MCU of the board. Throws std::runtime_error if simavr cannot load it.
    explicit AvrCore(const ElfImage& elf, const AvrCoreConfig& config = {});

    /// Checks, without building a core, that simavr's own ELF loader reads
    /// `elf` and lays its program out inside the flash (what the constructor
    /// needs); throws std::runtime_error naming the file otherwise.
    static void check_loadable(const ElfImage& elf, const McuDescription& mcu);
    ~AvrCore();
    AvrCore(const AvrCore&) = delete;
    AvrCore& operator=(const AvrCore&) = delete;

    /// The simavr instance, for parts to attach their IRQs and timers to.
    avr_t* raw() { return avr_.get(); }
    const ElfImage& elf() const { return elf_; }
    Cycles cycle() const { return *cycle_; }
    const BoardDescription& board() const { return board_; }
    /// The pin-change groups restored where simavr's core lacks them (empty on the ATmega328P).
    std::vector<int> restored_pin_change_groups() const { return pin_change_->restored_groups(); }
    const McuDescription& mcu() const { return *board_.mcu; }
    /// The board's clock [Hz]: every conversion between cycles and seconds uses it.
    uint32_t clock_hz() const { return board_.clock_hz; }
    double seconds() const { return cycles_to_s(cycle(), clock_hz()); }
    /// Program counter as a flash byte address.
    uint32_t pc() const { return *pc_; }
    uint16_t stack_pointer() const { return static_cast<uint16_t>(data_[spl_] | (data_[sph_] << 8)); }
    /// The return address a CALL or an interrupt pushed with its high byte at
    /// data address `first` (SP + 1 right after the push): mcu().pc_bytes
    /// bytes, high first, a word address; returned as a flash byte address.
    uint32_t return_address_at(uint32_t first) const;
    /// A byte of data space (registers, I/O, SRAM), as the firmware would read it
    /// without side effects.
    uint8_t data(uint16_t address) const;
    /// Writes a byte of SRAM as a debugger does (no write handler runs);
    /// throws std::out_of_range for an address below SRAM or past RAMEND.
    void set_sram(uint16_t address, uint8_t value);
    SimavrLog& log() { return log_; }

    /// Runs until the AVR clock reaches `target` (within one instruction), or a
    /// part calls request_stop() / a stop_after() deadline passes (kCondition).
    RunStop run_until(Cycles target);

    /// What an instruction hook reads of the machine after an instruction.
    /// kPcSpCycle: only pc(), stack_pointer() and cycle() (the profilers);
    /// fast-forward then stays on and shows the hook every instruction of a
    /// skipped pass, with the PC, SP and cycle each had (run_instruction_hooks).
    /// kAnything (avr-gdb): nothing is skipped while the hook is installed.
    enum class HookReads { kAnything, kPcSpCycle };
    /// Adds a hook called after every instruction (in the order added) while
    /// any hook is installed: run_until then steps one instruction per
    /// avr_run, which is exact but slower (profiling, debugging). `owner`
    /// identifies it for remove_instruction_hook(); one hook per owner (adding
    /// again replaces it). Keep hooks short; they must not throw.
    ///
    /// `state_changes` (kPcSpCycle hooks, optional): a count of the changes
    /// of the hook's own state, for a hook that decides from the PC, the SP
    /// and that state alone, and reads the cycle only where the state
    /// changes (the loop profiler). Fast-forward then shows it one pass of
    /// skipped passes that repeat one path (same PCs, same SPs), and the
    /// others only if that one changed its state: identical passes from an
    /// unchanged state change nothing either.
    void add_instruction_hook(const void* owner, std::function<void()> hook, HookReads reads = HookReads::kAnything,
                              std::function<uint64_t()> state_changes = {});
    void remove_instruction_hook(const void* owner);
    bool has_instruction_hooks() const { return !instruction_hooks_.empty(); }
    /// True if every installed instruction hook is HookReads::kPcSpCycle.
    bool hooks_replayable() const { return opaque_hooks_.empty(); }
    /// Calls every instruction hook once, as after an instruction
    /// (fast-forward's own steps, and its replays of skipped passes).
    void run_instruction_hooks() const {
        for (const auto& h : instruction_hooks_) h.hook();
    }
    /// An installed instruction hook (in the order called).
    struct InstructionHook {
        const void* owner;
        std::function<void()> hook;
        std::function<uint64_t()> state_changes;  ///< empty: show it every instruction
    };
    const std::vector<InstructionHook>& instruction_hooks() const { return instruction_hooks_; }

    /// A function called before every instruction (PC at it, registers as it
    /// will see them) while set: right after each avr_run, before any stop,
    /// so no instruction is skipped between run_until calls; nullptr
    /// switches it off. Unlike instruction
    /// hooks it may be switched on and off from an IRQ callback in the middle
    /// of a run: while it is on, simavr runs one instruction per avr_run
    /// (run_cycle_limit 1, which gives identical results), so a part can
    /// step only short stretches (the race detector steps only ISRs). One
    /// watch at a time; it must not throw.
    using StepWatch = void (*)(void* context);
    void set_step_watch(StepWatch watch, void* context);

    /// Asks the running run_until to return after the current instruction
    /// (the one whose I/O raised the callback; from a cycle-timer callback,
    /// before the next one), wherever simavr's batch of instructions would
    /// have ended, so a stop's cycle does not depend on how the run was
    /// batched (fast-forward, run_cycle_limit). Safe to call from IRQ and
    /// cycle-timer callbacks.
    void request_stop();
    /// Requests a stop exactly `delay` cycles from now (a cycle timer).
    void stop_after(Cycles delay);
    bool stop_requested() const { return stop_requested_; }
    /// Forgets a stop request once the caller has acted on it, so the next
    /// run_until runs again (scenario steps run the core many times).
    void clear_stop_request() { stop_requested_ = false; }

    /// Runs one instruction at a time until `condition()` is true after an
    /// instruction, or `target` is reached. Slower than run_until(target):
    /// use it for short phases that must stop on a PC or register change.
    RunStop run_until(Cycles target, const std::function<bool()>& condition);

    /// AVR reset, as by the RESET pin: simavr's avr_reset (I/O registers
    /// cleared, PC = 0, SP = RAMEND, SREG and pending interrupts cleared, every
    /// cycle timer cancelled; SRAM and EEPROM keep their contents), the cycle
    /// count kept running, this class's set-up re-applied, then every reset
    /// listener in the order added, so parts re-arm their timers and re-read
    /// the registers. Call it between run_until calls, not from a callback.
    void reset();
    /// `fn` runs after each reset(); one listener per owner.
    void add_reset_listener(const void* owner, std::function<void()> fn);
    void remove_reset_listener(const void* owner);
    uint64_t resets() const { return resets_; }
    uint64_t watchdog_resets() const { return watchdog_resets_; }

    /// Runs until the firmware has returned from its first call to `function`,
    /// or `target`. Returns kCondition on return.
    ///
    /// Detection samples the CPU every kReturnSamplePeriod cycles, so the run
    /// batches instructions at full speed. The first sample whose PC lies in
    /// `function` finds the call's return address on the stack (the lowest
    /// stacked word that points just after a CALL/RCALL to `function`); the
    /// return is seen at the first later sample whose SP is back above that
    /// slot. `function` must run for at least a few sample periods (delay()
    /// does); the stop comes within a sample period of the RET, or later if
    /// the caller is then inside a callee.
    RunStop run_until_return_from(const ElfSymbol& function, Cycles target);
    static constexpr Cycles kReturnSamplePeriod = 256;

    /// Skips whole passes of busy-wait loops in free runs (hil/fast_forward.hpp);
    /// off by default. Not applied while instruction hooks or a step watch
    /// are installed (those runs step every instruction).
    void set_fast_forward(bool on);
    /// Declares a part's observing cycle timer replayable after a jump
    /// (hil/fast_forward.hpp: ReplayableTimer); withdrawn with its owner.
    void allow_replay(ReplayableTimer timer) {
        // cppcheck-suppress danglingLifetime ; a caller's local timer is withdrawn (forget_replay) before it ends
        replayable_.push_back(std::move(timer));
    }
    void forget_replay(const void* param);
    /// How a part's watch of an I/O register takes the reads simavr also
    /// notifies, and writes of the value the register holds: kIgnored if a
    /// notification of the register's unchanged value changes nothing in
    /// the part (then fast-forward may skip loops that read the register,
    /// or write it that value); kMatter otherwise.
    enum class IoReads { kMatter, kIgnored };
    /// simavr's memory IRQ of the I/O register at data address `address`
    /// (raised on every write and read), with `notify(param)` registered on
    /// it; parts watch registers only through this. Throws std::runtime_error
    /// if simavr has no IRQ for the address.
    struct avr_irq_t* watch_io(uint16_t address, void (*notify)(struct avr_irq_t*, uint32_t, void*), void* param,
                               IoReads reads);
    /// Withdraws a watch_io registration.
    void unwatch_io(uint16_t address, void (*notify)(struct avr_irq_t*, uint32_t, void*), void* param, IoReads reads);
    /// The fast-forward engine, or nullptr while it is off.
    const FastForward* fast_forward() const { return fast_forward_.get(); }
    /// simavr's run_cycle_limit outside run_until's stepping loops: 1 while a
    /// step watch is on (fast-forward restores it after stepping, during
    /// which an interrupt entry may have switched a watch on).
    Cycles free_run_limit() const;

    /// True if a watchdog reset is pending or simavr logged a new error: the
    /// run must stop stepping and return (run_until takes the event). simavr's
    /// watchdog swaps its run callback for one that resets the chip without
    /// the parts: stepping on would run it (FastForward checks this too).
    bool event_pending() const;

    /// A 16-bit word of flash at a byte address (little-endian, as fetched).
    uint16_t flash_word(uint32_t byte_address) const;

private:
    struct AvrDeleter {
        void operator()(avr_t* avr) const;
    };
    RunStop state_stop() const;
    /// Replaces simavr's RAM block by one covering all 64 KiB of data space.
    static void widen_data_space(avr_t* avr);

    ElfImage elf_;
    AvrCoreConfig config_;
    const BoardDescription& board_;
    /// simavr's cycle counter, PC and data space, and the MCU's SPL and SPH:
    /// cycle(), pc() and stack_pointer() run on every instruction of a
    /// profiled run, so they read them in place (set once avr_ exists; simavr
    /// never moves them).
    const uint64_t* cycle_ = nullptr;
    const uint32_t* pc_ = nullptr;
    const uint8_t* data_ = nullptr;
    uint16_t spl_ = 0, sph_ = 0;
    SimavrLog log_;
    /// Declared before avr_: simavr keeps pointers to its vectors until avr_ is freed.
    std::unique_ptr<PinChangeRestorer> pin_change_;
    std::unique_ptr<avr_t, AvrDeleter> avr_;
    std::unique_ptr<FastForward> fast_forward_;
    std::vector<ReplayableTimer> replayable_;
    std::unordered_map<uint16_t, IoWatchers> io_watchers_;
    bool stop_requested_ = false;
    /// A callback and who installed it (instruction hooks, reset listeners).
    struct OwnedCallback {
        const void* owner;
        std::function<void()> hook;
    };
    std::vector<InstructionHook> instruction_hooks_;
    std::vector<const void*> opaque_hooks_;  ///< owners of HookReads::kAnything hooks
    StepWatch step_watch_ = nullptr;
    void* step_watch_context_ = nullptr;
    /// run_until is stepping for instruction hooks or a condition (limit 1).
    bool stepping_ = false;
    std::vector<OwnedCallback> reset_listeners_;
    uint64_t resets_ = 0;
    uint64_t watchdog_resets_ = 0;
    uint64_t hard_errors_seen_ = 0;
    /// simavr's instruction loop; its watchdog swaps in a reset callback.
    void (*normal_run_)(avr_t*) = nullptr;
    /// Handles what event_pending() saw: kWatchdogReset or kSimavrError.
    RunStop take_event();
    void apply_setup();
};

}  // namespace ddmr::hil
