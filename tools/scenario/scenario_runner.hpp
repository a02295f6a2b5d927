#pragma once
// Runs one scenario (scenario.hpp) on the HIL: the firmware in simavr, the
// robot plant coupled, the host's serial adapter at the scenario's baud rate
// (hil/serial_line.hpp), and the steps executed in order in AVR time. The
// first failing step ends the scenario (as in Wokwi); `fail-serial` patterns
// are checked on every received line from the step that adds them.
//
// Verdicts: pass; fail (a check did not hold: exit 1); error (the scenario
// cannot run: exit 2, thrown before anything is written); firmware (crash,
// sleep with interrupts off, the plant diverged, or the scenario's timeout
// came first: exit 3).
//
// Outputs in `out_dir` (each written atomically, also on failure):
//   uart.txt     what the adapter received (at its baud rate), streamed
//                to the file as it arrives
//   truth.csv    the plant's ground truth at 1 kHz
//   eeprom.bin   the EEPROM at the end
//   eeprom_log.csv  the firmware's EEPROM log, decoded (time origin: the first write-serial)
//   isr.md       interrupt timing table
//   result.json  the verdict, every step with its AVR time, the failure
//   failure_window.vcd  (only if it did not pass) the last 0.5 s of AVR time
//                before the end: Uno pins, synthesised PWM and serial, ISRs

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "scenario/scenario.hpp"

namespace ddmr::tools::scenario {

/// How much of the received serial text the runner keeps [bytes]:
/// `wait-serial` and `expect-serial` search the last 64 KiB (68 s of
/// continuous output at 9600 baud), `fail-serial` the last 64 KiB of a line,
/// so memory stays flat however long a scenario runs (docs/scenarios.md).
inline constexpr std::size_t kSerialWindowBytes = std::size_t{64} * 1024;

enum class Verdict { kPass, kFail, kFirmware };
const char* to_string(Verdict v);
/// The process exit code of a verdict (exit_codes.hpp).
int exit_code(Verdict v);

struct StepOutcome {
    int line = 0;
    std::string kind;
    std::string text;
    bool passed = false;
    Cycles cycle = 0;       ///< AVR time when the step finished (or failed)
    std::string message;    ///< what was expected and what happened (on failure, or a note)
};

struct ScenarioResult {
    std::string name;
    std::filesystem::path file;
    Verdict verdict = Verdict::kPass;
    std::string message;           ///< one line: why it did not pass
    std::vector<StepOutcome> steps;  ///< the steps run (the last one failed if verdict != pass)
    Cycles cycles = 0;
    uint32_t clock_hz = 0;  ///< the board's clock: step cycles in seconds
    double sim_seconds = 0.0;
    double wall_seconds = 0.0;
    uint64_t uart_bytes = 0;       ///< what the adapter received (all of it in uart.txt)
    uint64_t framing_errors = 0;
};

/// Checks what a scenario names in its firmware and can be checked before a
/// run (the variables of expect-no-torn-reads: 2..8-byte variables in SRAM).
/// Throws std::invalid_argument "FILE:LINE: ..." naming the first problem.
void check_firmware_names(const Scenario& s);

/// Runs `s`, writing its artifacts to `out_dir` (created). Throws
/// std::runtime_error / std::invalid_argument for input errors before
/// anything is written.
/// With `update_golden`, expect-eeprom and expect-pose steps record what the
/// run gives instead of checking it (the golden files, and the pose values in
/// the scenario file at the step's lines), written only when every other
/// step passed.
ScenarioResult run_scenario(const Scenario& s, const std::filesystem::path& out_dir, bool progress = false,
                            bool update_golden = false);

}  // namespace ddmr::tools::scenario
