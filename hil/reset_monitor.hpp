#pragma once
// ResetMonitor: counts the restarts the firmware did not ask for (a jump or a
// call to address 0, or a return into it) and stops a run that restarts in a
// loop (issue 32: a sketch whose `new` links to `call 0` restarted 4,500
// times a second, and the run said nothing).
//
// The signal: avr-libc's start-up code (.init2) begins every start from the
// reset vector with `clr r1; out SREG, r1`, then sets SP. An I/O write
// callback on SREG compares simavr's PC with the address of that one `out`
// instruction: one compare per SREG write (firmware writes SREG rarely: ISR
// epilogues, `SREG = oldSREG`), none per pushed byte (a callback on SPL/SPH
// would run on every PUSH, POP, CALL and RET: simavr sets SP through
// _avr_set_r), none per instruction.
//
// A start is asked for after power-on and after AvrCore::reset() (the
// watchdog, a reset step): both through avr_reset, announced by the core's
// reset listeners. Any other start is unasked. At that moment SP is still
// the old one, so its origin is known when it was a call:
//   - CALL/RCALL 0, or ICALL/EICALL with Z = 0, pushed a return address at
//     SP + 1, and the flash word(s) before it decode to that call: the PC;
//   - otherwise a jump (JMP/RJMP/IJMP 0) or a RET into 0: simavr keeps no
//     previous PC, so only SP (and whether a zero return address sits just
//     below it) is said.
// The first unasked restart is told to the warning sink (default: stderr).
// More than kMaxPerWindow restarts within one simulated second stop the run
// (AvrCore::request_stop): loop() then describes it (run_failure.hpp:
// FailureKind::kResetLoop, exit reason `reset_loop`).
//
// A firmware without avr-libc's start-up (no `out SREG` within the first
// instructions after the reset vector's target) is not watched: watching()
// is false.
//
// Signals: SREG writes (I/O write callback); AvrCore reset listener.

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>

#include "hil/avr_core.hpp"

namespace ddmr::hil {

/// Counts events in a sliding window of cycles: the part of ResetMonitor
/// that decides when restarts are a loop.
class ResetRate {
public:
    /// More than this many restarts within one window is a loop.
    static constexpr std::size_t kMaxPerWindow = 10;
    /// `window_cycles` >= 1 (one simulated second: the clock in Hz).
    explicit ResetRate(Cycles window_cycles);
    /// Notes a restart at `cycle` (never less than the previous one). True
    /// when it is the (kMaxPerWindow + 1)th within less than one window.
    bool note(Cycles cycle);
    uint64_t count() const { return count_; }

private:
    Cycles window_;
    std::array<Cycles, kMaxPerWindow> last_{};  ///< the previous restarts, a ring
    std::size_t oldest_ = 0;                    ///< ring index of the oldest of them
    uint64_t count_ = 0;
};

/// An unasked restart and where it came from.
struct UnaskedReset {
    Cycles cycle = 0;   ///< when the start-up code began (the `out SREG`)
    uint16_t sp = 0;    ///< SP then: what the call or jump left
    std::string from;   ///< "`call 0` at PC 0x0a3c in setup()", or what is known of a jump
};

/// The run stopped: restarts came faster than ResetRate allows.
struct ResetLoop {
    Cycles cycle = 0;        ///< the restart that made it a loop
    uint64_t count = 0;      ///< unasked restarts so far
    std::string first_from;  ///< the first one's origin (UnaskedReset::from)
};

class ResetMonitor {
public:
    using WarningSink = std::function<void(const std::string& line)>;
    /// Watches `core` from power-on (build it before the first run_until).
    explicit ResetMonitor(AvrCore& core);
    ~ResetMonitor();
    ResetMonitor(const ResetMonitor&) = delete;
    ResetMonitor& operator=(const ResetMonitor&) = delete;

    /// False when the firmware has no start-up code to watch (see above).
    bool watching() const { return startup_pc_.has_value(); }
    /// Flash byte address of the start-up's `out SREG`, when watching.
    const std::optional<uint32_t>& startup_pc() const { return startup_pc_; }
    uint64_t count() const { return rate_.count(); }
    const std::optional<UnaskedReset>& first() const { return first_; }
    const std::optional<ResetLoop>& loop() const { return loop_; }
    /// Where the first unasked restart is told, one line without a newline
    /// (default: "ddmr-hil: warning: LINE" on stderr).
    void set_warning_sink(WarningSink sink) { sink_ = std::move(sink); }

private:
    static void on_sreg_write(struct avr_t* avr, uint16_t address, uint8_t value, void* param);
    void on_start();
    std::string origin(uint16_t sp) const;
    std::string in_function(uint32_t pc) const;

    AvrCore& core_;
    std::optional<uint32_t> startup_pc_;
    bool start_expected_ = true;  ///< power-on, or an AvrCore::reset() since the last start
    ResetRate rate_;
    std::optional<UnaskedReset> first_;
    std::optional<ResetLoop> loop_;
    WarningSink sink_;
};

/// The start-up code's `out SREG` in `core`'s flash: the reset vector's JMP
/// or RJMP target (or 0), then its first few instructions; nullopt if none.
std::optional<uint32_t> find_startup_sreg_write(const AvrCore& core);

}  // namespace ddmr::hil
