#pragma once
// The parsers of a scenario's steps, one per family of steps, each in its own
// file; parse_step() refuses an unknown kind and asks each family in turn.
// A family returns nothing for a kind that is not its own.

#include <optional>
#include <string>

#include "scenario/yaml_ctx.hpp"

namespace ddmr::tools::scenario::yaml {

/// The step `kind` with its value `c` (ScenarioError when wrong).
StepAction parse_step(const std::string& kind, const Ctx& c);

std::optional<StepAction> parse_serial_step(const std::string& kind, const Ctx& c);
std::optional<StepAction> parse_pin_step(const std::string& kind, const Ctx& c);
std::optional<StepAction> parse_firmware_step(const std::string& kind, const Ctx& c);
std::optional<StepAction> parse_plant_step(const std::string& kind, const Ctx& c);
std::optional<StepAction> parse_fault_step(const std::string& kind, const Ctx& c);

}  // namespace ddmr::tools::scenario::yaml
