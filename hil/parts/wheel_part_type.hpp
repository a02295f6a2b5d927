#pragma once
// Builds the PartType of a wheel part (wheel_part_spec.hpp) from its spec:
// its board-file keys are its inputs by role (or its output signals), `wheel`
// and `reversed`. One call per driver or encoder file.

#include <string>
#include <utility>
#include <vector>

#include "hil/parts/part.hpp"

namespace ddmr::hil {

/// A motor driver type: `word` (`driver:` in wheels:, `type:` in parts:),
/// one description per input role of `spec`.
PartType motor_driver_type(std::string word, std::string summary, std::string datasheet, MotorDriverSpec spec,
                           const std::vector<std::pair<DriverRole, std::string>>& inputs);

/// An encoder type: one description per output signal of `spec`.
PartType encoder_type(std::string word, std::string summary, std::string datasheet, EncoderSpec spec,
                      const std::vector<std::string>& descriptions, std::string reversed_means);

}  // namespace ddmr::hil
