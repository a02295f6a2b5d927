#pragma once
// `run --verify-fast-forward`: the run as `run` does it (artifacts in the
// output folder), and beside it, on a second thread, the same run without
// fast-forward (its artifacts in a temporary folder, removed). The two meet
// every 10 ms of AVR time (and at the boot's end and the run's end) and
// compare their machine states (hil/machine_state.hpp: cycle, PC, registers,
// I/O, SRAM, EEPROM, the plant). At the first checkpoint that differs, the
// runs are repeated from reset up to stops between the last equal checkpoint
// and it (bisection: about 18 repetitions of the prefix), to name the first
// stop at which they differ, with the PC and every byte and value that
// differs. docs/fast-forward.md describes the output.

#include <cstdint>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "firmware_run.hpp"
#include "hil/machine_state.hpp"

namespace ddmr::tools {

/// The first stop at which the runs with and without fast-forward differ.
struct FastForwardDifference {
    hil::Cycles last_equal_cycle = 0;  ///< the last stop at which they were equal (0: reset)
    hil::MachineState with_ff, without_ff;  ///< the states at the first stop that differs
    /// True once the stop was narrowed down by repeating the runs; false:
    /// the checkpoint (a difference already at the boot's end, where the
    /// runs cannot be stopped earlier).
    bool narrowed = false;
    std::string function_with_ff, function_without_ff;  ///< the functions holding the PCs ("" if none)
    hil::StateComparison comparison;
};

struct FastForwardVerification {
    uint64_t checkpoints_equal = 0;    ///< checkpoints at which both runs were equal
    hil::Cycles checked_to_cycle = 0;  ///< the last of them
    std::optional<FastForwardDifference> difference;
};

struct VerifiedRun {
    FirmwareRunResult result;  ///< the run with fast-forward (its artifacts are in options.out_dir)
    FastForwardVerification verification;
};

/// Runs `options` (fast_forward must be on) in lockstep with its copy
/// without fast-forward. Throws as run_firmware does, before anything runs.
VerifiedRun run_verifying_fast_forward(const FirmwareRunOptions& options);

/// The engine of it: `options` (run A: the artifacts, "with fast-forward")
/// in lockstep with `other` (run B, "without"; its artifacts discarded).
/// Tests give B a difference of their own to find.
VerifiedRun run_in_lockstep_with(const FirmwareRunOptions& options, const FirmwareRunOptions& other);

/// fast_forward_verify.json's content (docs/fast-forward.md).
nlohmann::json verification_json(const FastForwardVerification& v, uint32_t clock_hz);
/// One line: "equal at N checkpoints up to t = ..." or where they first differ.
std::string verification_line(const FastForwardVerification& v, uint32_t clock_hz);

}  // namespace ddmr::tools
