#include "hil/robot_rig.hpp"

namespace ddmr::hil {

RobotRig::RobotRig(const ElfImage& elf, const RigConfig& config)
    : config_(config),
      core_(elf, config.core),
      uart_(core_, config.uart_timing),
      eeprom_(core_),
      eeprom_timing_(core_, config.eeprom_timing),
      driver_(core_, config.board),
      encoders_(core_, config.board),
      robot_(config.plant),
      coupler_(core_, robot_, driver_, encoders_, config.coupler),
      variables_(core_.elf(), core_) {}

}  // namespace ddmr::hil
