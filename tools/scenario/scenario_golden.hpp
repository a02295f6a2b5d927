#pragma once
// --update-golden: what a scenario run recorded (expect-eeprom's files,
// expect-pose's values), written only if every other step passed.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "plant/diff_drive_kinematics.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_runner.hpp"

namespace ddmr::tools::scenario {

/// One recorded value: the file's new bytes, or the pose for the step's line.
struct Golden {
    int line = 0;
    std::optional<std::filesystem::path> file;  ///< expect-eeprom: the golden file
    std::string bytes;
    std::optional<plant::Pose> pose;  ///< expect-pose: new x_m, y_m (and theta_rad when given)
};

/// Writes `golden` (the files, and the poses into the scenario file, each in
/// its own step's lines) if `r` passed; says what it did in r.message.
void apply_golden(const Scenario& s, const std::vector<Golden>& golden, ScenarioResult& r);

}  // namespace ddmr::tools::scenario
