#include "hil/motor_driver_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace ddmr::hil {
namespace {

using plant::BridgeState;

std::vector<int> driver_pins(const BoardWiring& board) {
    std::vector<int> pins;
    for (const WheelWiring& w : board.wheel) {
        for (const InputWire& in : w.motor.input) {
            if (in.used && !in.tied_high && std::find(pins.begin(), pins.end(), in.pin) == pins.end()) {
                pins.push_back(in.pin);
            }
        }
    }
    return pins;
}

BridgeState mirrored(BridgeState s, bool reversed) {
    if (!reversed) return s;
    if (s == BridgeState::forward) return BridgeState::reverse;
    if (s == BridgeState::reverse) return BridgeState::forward;
    return s;
}

template <class T, class V>
void set_role(T& fields, DriverRole r, V v) {
    switch (r) {
        case DriverRole::pwm: fields.pwm = v; break;
        case DriverRole::dir: fields.dir = v; break;
        case DriverRole::en: fields.en = v; break;
        case DriverRole::in1: fields.in1 = v; break;
        case DriverRole::in2: fields.in2 = v; break;
        case DriverRole::stby: fields.stby = v; break;
        case DriverRole::sleep: fields.sleep = v; break;
    }
}

}  // namespace

MotorDriverReader::MotorDriverReader(AvrCore& core, const BoardWiring& board)
    : board_((validate(board), board)), pins_(core, driver_pins(board)) {
    for (std::size_t m = 0; m < 2; ++m) {
        const MotorWiring& w = board_.wheel[m].motor;
        wheel_[m].driver = w.driver;
        wheel_[m].reversed = w.reversed;
        for (std::size_t r = 0; r < kDriverRoleCount; ++r) {
            const InputWire& in = w.input[r];
            if (in.used) wheel_[m].inputs.push_back(Input{static_cast<DriverRole>(r), in.tied_high, in.pin});
        }
    }
}

bool MotorDriverReader::level_of(const Input& in, Cycles cycle) const {
    if (in.tied_high) return true;
    // Output: its level; input: the pull-up reads high, a floating input low.
    return pins_.level_at(in.pin, cycle);
}

double MotorDriverReader::duty_of(const Input& in) const {
    if (in.tied_high) return 1.0;
    return pins_.duty(in.pin);
}

bool MotorDriverReader::input_level(std::size_t m, DriverRole r, Cycles cycle) const {
    for (const Input& in : wheel_[m].inputs) {
        if (in.role == r) return level_of(in, cycle);
    }
    return false;
}

BridgeState MotorDriverReader::state_at(std::size_t m, Cycles cycle) const {
    const Wheel& w = wheel_[m];
    plant::DriverInputLevels levels;
    for (const Input& in : w.inputs) set_role(levels, in.role, level_of(in, cycle));
    return mirrored(plant::bridge_state(w.driver, levels), w.reversed);
}

Cycles MotorDriverReader::next_change_after(std::size_t m, Cycles cycle) const {
    Cycles next = kNever;
    for (const Input& in : wheel_[m].inputs) {
        if (!in.tied_high) next = std::min(next, pins_.next_change_after(in.pin, cycle));
    }
    return next;
}

plant::BridgeInput MotorDriverReader::input_at(std::size_t m, Cycles cycle) const {
    const Wheel& w = wheel_[m];
    plant::DriverInputDuties duties;
    for (const Input& in : w.inputs) set_role(duties, in.role, duty_of(in));
    const plant::BridgeAverage avg = plant::average_bridge(w.driver, duties);
    plant::BridgeInput b;
    b.state = state_at(m, cycle);
    const double forward = w.reversed ? avg.reverse : avg.forward;
    const double reverse = w.reversed ? avg.forward : avg.reverse;
    if (forward > reverse) {
        b.duty = forward - reverse;
        b.forward = true;
    } else if (reverse > forward) {
        b.duty = reverse - forward;
        b.forward = false;
    } else {
        // Not driven: the direction the inputs select, for the logs (the
        // thesis's shield: its DIR pin).
        b.duty = 0.0;
        b.forward = w.driver == plant::DriverType::dir_pwm ? duties.dir >= 0.5 : true;
        if (w.reversed && w.driver == plant::DriverType::dir_pwm) b.forward = !b.forward;
    }
    b.brake = avg.brake;
    return b;
}

std::vector<std::string> MotorDriverReader::wiring_warnings() const {
    std::vector<std::string> out;
    for (std::size_t m = 0; m < 2; ++m) {
        for (const Input& in : wheel_[m].inputs) {
            if (in.tied_high || pins_.ever_output(in.pin)) continue;
            const bool pullup = pins_.mode(in.pin) == PinMode::input_pullup;
            out.push_back(fmt::format("pin {} ({}) is never set as an output: the driver sees only {}",
                                      uno_pin_label(in.pin).substr(uno_pin_label(in.pin)[0] == 'D' ? 1 : 0),
                                      input_label(board_, m, in.role),
                                      pullup ? "the pull-up (high)" : "a floating input (read as low)"));
        }
    }
    return out;
}

}  // namespace ddmr::hil
