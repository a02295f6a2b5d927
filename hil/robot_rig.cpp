#include "hil/robot_rig.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace ddmr::hil {
namespace {

/// The plant as the board wires it: each wheel's driver chip and encoder channels.
plant::RobotParams wired(plant::RobotParams p, const BoardWiring& board) {
    for (std::size_t m = 0; m < 2; ++m) {
        p.chip[m] = plant::chip_of(board.wheel[m].motor.driver);
        // A wheel without an encoder keeps the plant's (unwired) single channel.
        p.encoder[m].channels = std::max(1, static_cast<int>(board.wheel[m].encoder.signals()));
    }
    return p;
}

/// The robot at the world's start pose (none: the origin, heading +x),
/// stopped by its walls. `world` must outlive the robot.
plant::Robot at_start(const plant::RobotParams& params, const plant::World& world) {
    plant::Robot robot(params);
    if (world.start) robot.reset(*world.start);
    if (!world.walls.empty()) robot.set_world(&world);
    return robot;
}

/// The USART the host's adapter is on: config.host_usart, else the board's console.
const UsartDesc& host_usart(const AvrCore& core, const RigConfig& config) {
    const BoardDescription& board = core.board();
    if (!config.host_usart) return board.console();
    const std::string port = serial_port_name(*config.host_usart);
    if (!parse_serial_port(board, port)) {
        throw std::invalid_argument("the host serial port " + port + " does not exist on the " + board.label + " (" +
                                    board.mcu->label + "); its serial ports are " + serial_port_list(board));
    }
    const UsartDesc& usart = board.mcu->usarts[static_cast<std::size_t>(*config.host_usart)];
    check_host_serial_pins(config.board, usart);
    return usart;
}

/// The core's configuration on the board the wiring names (its MCU and clock).
AvrCoreConfig core_on_board(const RigConfig& config) {
    AvrCoreConfig c = config.core;
    c.board = config.board.model;
    return c;
}

}  // namespace

RobotRig::RobotRig(const ElfImage& elf, const RigConfig& config)
    : config_(config),
      core_(elf, core_on_board(config)),
      uart_(core_, host_usart(core_, config), config.uart_timing),
      eeprom_(core_),
      eeprom_timing_(core_, config.eeprom_timing),
      timers_(core_),
      robot_(at_start(wired(config.plant, config.board), config_.world)),
      parts_(core_, config.board.parts, PartRegistry::global(), [this] { return robot_.pose(); }, &config_.world),
      world_truth_(config_.world, robot_),
      driver_(core_, config.board, &parts_),
      encoders_(core_, config.board),
      coupler_(core_, robot_, driver_, encoders_, config.coupler, &parts_),
      variables_(core_.elf(), core_),
      reset_monitor_(core_) {
    // The sensors drive their outputs from power-on: the pins start at the
    // encoders' levels, so the first edge is a change the firmware sees.
    for (unsigned m = 0; m < 2; ++m) {
        for (unsigned s = 0; s < config_.board.wheel[m].encoder.signals(); ++s) {
            encoders_.drive_now(m, s, robot_.encoder_level(m, s));
        }
    }
}

std::vector<std::string> RobotRig::extra_truth_columns() const {
    std::vector<std::string> columns = world_truth_.columns();
    for (std::string& c : parts_.truth_columns()) columns.push_back(std::move(c));
    return columns;
}

void RobotRig::extra_truth_values(std::vector<double>& out) const {
    world_truth_.values(out);
    parts_.truth_values(out);
}

std::vector<std::string> RobotRig::warnings() const {
    std::vector<std::string> out = driver_.wiring_warnings();
    for (std::string& w : parts_.warnings()) out.push_back(std::move(w));
    return out;
}

}  // namespace ddmr::hil
