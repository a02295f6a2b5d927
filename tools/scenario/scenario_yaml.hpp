#pragma once
// Loads and validates a scenario file (scenario.hpp; format in
// docs/scenarios.md). Everything is checked before anything runs: an unknown
// key, a wrong type, a bad value, an unknown step or a path that leaves the
// scenario's folder is refused with one line "FILE:LINE: key 'K': what is
// wrong" (ScenarioError).
//
// Paths inside a scenario are relative to its folder and must stay inside
// it; `firmware: reference` (the default) is the reference sketch built by
// this project. A firmware given on the command line replaces the file's.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "scenario/scenario.hpp"

namespace ddmr::tools::scenario {

class ScenarioError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct LoadOptions {
    std::filesystem::path reference_firmware;           ///< what `firmware: reference` means
    std::optional<std::filesystem::path> firmware_override;  ///< --firmware
};

Scenario load_scenario(const std::filesystem::path& file, const LoadOptions& options);
/// Same, from text; `file` names it in messages and anchors relative paths.
Scenario parse_scenario(std::string_view yaml_text, const std::filesystem::path& file, const LoadOptions& options);

/// "500ms", "1.5 s", "250us", "16000 cycles" -> cycles at `clock_hz`
/// (rounded to the nearest cycle). Throws std::invalid_argument naming the
/// text: no unit, negative, NaN, too large.
Cycles parse_duration(std::string_view text, uint32_t clock_hz);

}  // namespace ddmr::tools::scenario
