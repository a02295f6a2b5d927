#pragma once
// RobotRig: the Uno, the L298 shield and the robot wired together, the
// "board" that connects the parts to one AvrCore:
//
//   UartLink          the host's USART (Serial = USART0, or config.host_usart) <-> host (case bytes in, report out)
//   EepromPort        EEPROM contents (preload, read back)
//   EepromWriteTiming EEPE held for the datasheet write time (or simavr's instant writes)
//   PhaseCorrectTimers the timers' phase-correct PWM modes simavr 1.6 lacks, with the datasheet's flags and TCNT
//   MotorDriverReader pin waveforms + driver truth tables => bridge state (pins per BoardWiring)
//   plant::Robot      motors, driver, battery, encoders, kinematics
//   PlantCoupler      steps the plant in lockstep, one step ahead of the AVR
//   EncoderInjector   plant edges => encoder pins at their exact cycles (levels from power-on)
//   FirmwareVariables globals by ELF symbol
//   PartSet           the board's `parts:` (a 74HC595, ...), built by type from the PartRegistry;
//                     they see the robot's pose and the world (RigConfig::world)
//   ResetMonitor      restarts the firmware did not ask for (a call to 0): counted, a loop stops the run
//
// Construction validates the configuration (throws with the bad value).

#include <memory>
#include <optional>

#include "hil/avr_core.hpp"
#include "hil/board.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/eeprom_write_timing.hpp"
#include "hil/elf_image.hpp"
#include "hil/encoder_injector.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/motor_driver_reader.hpp"
#include "hil/phase_correct_timer.hpp"
#include "hil/plant_coupler.hpp"
#include "hil/parts/part_set.hpp"
#include "hil/world_truth.hpp"
#include "hil/reset_monitor.hpp"
#include "hil/uart_link.hpp"
#include "plant/robot.hpp"
#include "plant/robot_params.hpp"
#include "plant/world.hpp"

namespace ddmr::hil {

struct RigConfig {
    plant::RobotParams plant = plant::default_robot_params();
    BoardWiring board = default_board();
    /// Around the robot (docs/world.md): lines, walls, the start pose. The
    /// default is the plain floor, the robot at the origin heading +x.
    plant::World world{};
    CouplerConfig coupler{};
    EepromTimingMode eeprom_timing = EepromTimingMode::kDatasheet;
    UartTiming uart_timing = UartTiming::kChip;
    AvrCoreConfig core{};  ///< its `board` is replaced by board.model (the wiring names the board)
    /// The USART the host's serial adapter is on (n of Serialn: 1 for Serial1
    /// on a Mega); unset: the board's console (Serial). The MCU must have it,
    /// and the wiring must not use its pins.
    std::optional<int> host_usart;
};

class RobotRig {
public:
    RobotRig(const ElfImage& elf, const RigConfig& config);
    RobotRig(const RobotRig&) = delete;
    RobotRig& operator=(const RobotRig&) = delete;

    AvrCore& core() { return core_; }
    const AvrCore& core() const { return core_; }
    UartLink& uart() { return uart_; }
    EepromPort& eeprom() { return eeprom_; }
    EepromWriteTiming& eeprom_timing() { return eeprom_timing_; }
    const PhaseCorrectTimers& timers() const { return timers_; }
    MotorDriverReader& driver() { return driver_; }
    /// The run's warnings so far: the wiring's (MotorDriverReader::wiring_warnings), then the parts'.
    [[nodiscard]] std::vector<std::string> warnings() const;
    /// The board's `parts:` (hil/parts/part_set.hpp).
    const PartSet& parts() const { return parts_; }
    PartSet& parts() { return parts_; }
    /// truth.csv's columns after the plant's: the world's (world_truth.hpp),
    /// then the parts' ("NAME.COLUMN"), and their values now.
    std::vector<std::string> extra_truth_columns() const;
    void extra_truth_values(std::vector<double>& out) const;
    EncoderInjector& encoders() { return encoders_; }
    plant::Robot& robot() { return robot_; }
    PlantCoupler& coupler() { return coupler_; }
    FirmwareVariables& variables() { return variables_; }
    ResetMonitor& reset_monitor() { return reset_monitor_; }
    const ResetMonitor& reset_monitor() const { return reset_monitor_; }
    const RigConfig& config() const { return config_; }
    /// The world around the robot, which the robot and the parts read at
    /// each step: a scenario moves its obstacles here (move-obstacle).
    plant::World& world() { return config_.world; }

private:
    RigConfig config_;
    AvrCore core_;
    UartLink uart_;
    EepromPort eeprom_;
    EepromWriteTiming eeprom_timing_;
    PhaseCorrectTimers timers_;
    plant::Robot robot_;  ///< at the world's start before the parts, which read its pose when built
    PartSet parts_;       ///< before the driver, which reads their outputs
    WorldTruth world_truth_;
    MotorDriverReader driver_;
    EncoderInjector encoders_;
    PlantCoupler coupler_;
    FirmwareVariables variables_;
    ResetMonitor reset_monitor_;
};

}  // namespace ddmr::hil
