#pragma once
// calibrate's confirmation in the HIL: the real firmware on the fitted plant,
// its own dump against each robot log (calibrate_command.cpp).

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "calibrate/robot_log.hpp"
#include "exit_codes.hpp"

namespace ddmr::tools {

/// The HIL confirmation: its part of calibration.json, of report.md, its line on stdout.
struct HilConfirmation {
    nlohmann::json json;
    std::string md;
    std::string summary;
    int exit_code = kExitOk;
};

/// The real firmware (`firmware`; none: not run, --no-hil) in the HIL on the
/// fitted plant (out/plant.yaml), its dump (out/hil/) against each log. A
/// failed run is reported, not thrown: the fit's outputs are still written.
HilConfirmation confirm_in_hil(const std::optional<std::string>& firmware, const std::vector<calibrate::RobotLog>& all,
                               int case_number, const std::filesystem::path& out,
                               const std::function<void(const std::string&)>& say);

}  // namespace ddmr::tools
