#pragma once
// Routes simavr's log output (a process-wide hook in simavr 1.6) to the
// SimavrLog of the AvrCore that produced it. Messages are counted per level
// and the first few kept for summary.json; echo to stderr is opt-in (-v), since
// simavr 1.6 warns on every OCR write in phase-correct PWM mode.

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

namespace ddmr::hil {

class SimavrLog {
public:
    /// simavr levels (sim_avr.h): 1 output, 2 error, 3 warning, 4 trace, 5 debug.
    static constexpr int kLevelError = 2;
    static constexpr int kLevelWarning = 3;
    static constexpr std::size_t kKeepFirst = 20;

    void record(int level, std::string message);

    /// Echo every recorded message to this stream (nullptr: off, the default).
    void set_echo(std::FILE* stream) { echo_ = stream; }

    uint64_t errors() const { return errors_; }
    /// Messages at simavr's error level (invalid opcodes, bad accesses...).
    uint64_t hard_errors() const { return hard_errors_; }
    /// The first of them, if any.
    const std::string& first_error() const { return first_error_; }
    uint64_t warnings() const { return warnings_; }
    /// The first kKeepFirst distinct messages, in order.
    const std::vector<std::string>& first_messages() const { return first_; }
    /// How often each distinct message was logged.
    const std::map<std::string, uint64_t>& counts() const { return counts_; }

private:
    std::FILE* echo_ = nullptr;
    uint64_t errors_ = 0;
    uint64_t warnings_ = 0;
    uint64_t hard_errors_ = 0;
    std::string first_error_;
    std::vector<std::string> first_;
    std::map<std::string, uint64_t> counts_;
};

/// Installs the project's simavr logger once per process (thread-safe).
/// Messages of an avr_t whose `custom.data` points at a SimavrLog go there;
/// messages with no avr_t (the ELF loader) go to the thread's current loading
/// log, set by LoadingLogScope, else to stderr.
void install_simavr_logger();

/// While alive, simavr messages without an avr_t on this thread go to `log`.
class LoadingLogScope {
public:
    explicit LoadingLogScope(SimavrLog* log);
    ~LoadingLogScope();
    LoadingLogScope(const LoadingLogScope&) = delete;
    LoadingLogScope& operator=(const LoadingLogScope&) = delete;

private:
    SimavrLog* previous_;
};

}  // namespace ddmr::hil
