#pragma once
// The JSON and CSV pieces of `ddmr-hil run`'s outputs (summary.json,
// isr.json, loop_profile.csv), from the run's plain results.

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "hil/board.hpp"
#include "hil/encoder_injector.hpp"
#include "hil/firmware_report.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/loop_profiler.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/robot.hpp"

namespace ddmr::tools {

nlohmann::json report_json(const hil::FirmwareReport& r);
/// compute / wait / period statistics for all iterations and for those with
/// and without an EEPROM write in their compute part.
nlohmann::json loop_profile_json(const std::vector<hil::LoopIteration>& its, uint32_t clock_hz);
std::string loop_profile_table(const std::vector<hil::LoopIteration>& its, uint32_t clock_hz);
nlohmann::json isr_json(const hil::IsrSummary& s);
nlohmann::json pose_json(const plant::Pose& p);
/// summary.json's `contacts` (a world with walls): how many times the body
/// met a wall, and the first Robot::kContactLog of them: time, point, speed.
nlohmann::json contacts_json(const plant::Robot& robot);
/// summary.json's `encoder`: per channel its wiring and counts.
nlohmann::json encoder_json(const hil::BoardWiring& board, const std::array<hil::EncoderChannelStats, 2>& stats);

}  // namespace ddmr::tools
