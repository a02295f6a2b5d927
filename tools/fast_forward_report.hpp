#pragma once
// summary.json's "fast_forward" section: what the run skipped of the
// firmware's busy-wait loops (hil/fast_forward.hpp), and why loops it came by
// often were not skipped. docs/fast-forward.md describes the fields.

#include <nlohmann/json.hpp>

#include "hil/cycle_time.hpp"

namespace ddmr::hil {
class AvrCore;
}

namespace ddmr::tools {

/// The section for a run of `cycles_total` cycles; {"enabled": false} when
/// the run executed every instruction.
nlohmann::json fast_forward_json(const hil::AvrCore& core, hil::Cycles cycles_total);

}  // namespace ddmr::tools
