#pragma once
// What the engine's firmware diagnostics (issue 32) put in summary.json and
// on stderr, for every front end:
//   - calls to address 0 found in the ELF before it runs (hil/zero_calls.hpp);
//   - restarts the firmware did not ask for (hil/reset_monitor.hpp).

#include <nlohmann/json.hpp>

#include "hil/elf_image.hpp"
#include "hil/reset_monitor.hpp"
#include "hil/zero_calls.hpp"

namespace ddmr::tools {

/// Scans `elf` for unguarded calls to 0; with `warn`, one line each on stderr
/// ("ddmr-hil: warning: firmware F: `call 0` at ...").
hil::ZeroCallReport scan_zero_calls(const hil::ElfImage& elf, bool warn);

/// summary.json's `calls_to_address_0`: {"calls": [{"pc", "instruction",
/// "function"}], "unresolved_weak": [names]}.
nlohmann::json zero_calls_json(const hil::ZeroCallReport& report);

/// summary.json's `unasked_resets`: {"count", "first": {"cycle", "sp", "from"}
/// or null}; null when the firmware has no start-up code to watch.
nlohmann::json unasked_resets_json(const hil::ResetMonitor& monitor);

}  // namespace ddmr::tools
