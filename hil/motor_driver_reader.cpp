#include "hil/motor_driver_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ddmr::hil {
namespace {

using plant::BridgeState;

std::vector<int> driver_pins(const BoardWiring& board) {
    std::vector<int> pins;
    for (const WheelWiring& w : board.wheel) {
        for (const InputWire& in : w.motor.input) {
            if (in.on_pin() && std::find(pins.begin(), pins.end(), in.pin) == pins.end()) {
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

/// The field of a driver's truth-table inputs that `r` feeds (levels or duties).
template <class T, class V>
V T::*field_of(DriverRole r) {
    switch (r) {
        case DriverRole::pwm: return &T::pwm;
        case DriverRole::dir: return &T::dir;
        case DriverRole::en: return &T::en;
        case DriverRole::in1: return &T::in1;
        case DriverRole::in2: return &T::in2;
        case DriverRole::stby: return &T::stby;
        case DriverRole::sleep: return &T::sleep;
    }
    return &T::pwm;
}

}  // namespace

MotorDriverReader::MotorDriverReader(AvrCore& core, const BoardWiring& board, const PartSet* parts)
    : board_((validate(board), board)), pins_(core, driver_pins(board)), core_clock_hz_(core.clock_hz()) {
    if (board.model != core.board().model) {
        throw std::logic_error(std::string("MotorDriverReader: the wiring is for board ") +
                               board_description(board.model).key + ", the core runs " + core.board().key);
    }
    for (std::size_t m = 0; m < 2; ++m) {
        const MotorWiring& w = board_.wheel[m].motor;
        wheel_[m].driver = w.driver;
        wheel_[m].reversed = w.reversed;
        for (std::size_t r = 0; r < kDriverRoleCount; ++r) {
            const InputWire& in = w.input[r];
            if (!in.used) continue;
            const auto role = static_cast<DriverRole>(r);
            const LogicSignal* signal = nullptr;
            if (!in.part_output.empty()) {
                if (parts == nullptr) throw std::logic_error("MotorDriverReader: " + in.part_output + " needs the parts");
                signal = &parts->signal(in.part_output);
            }
            wheel_[m].inputs[wheel_[m].count++] =
                Input{role, in.tied_high, in.pin, signal, field_of<plant::DriverInputLevels, bool>(role),
                      field_of<plant::DriverInputDuties, double>(role)};
        }
    }
}

bool MotorDriverReader::level_of(const Input& in, Cycles cycle) const {
    if (in.tied_high) return true;
    if (in.signal != nullptr) return in.signal->level_at(cycle);
    // Output: its level; input: the pull-up reads high, a floating input low.
    return pins_.level_at(in.pin, cycle);
}

double MotorDriverReader::duty_of(const Input& in) const {
    if (in.tied_high) return 1.0;
    if (in.signal != nullptr) return in.signal->duty();
    return pins_.duty(in.pin);
}

bool MotorDriverReader::input_level(std::size_t m, DriverRole r, Cycles cycle) const {
    const Wheel& w = wheel_[m];
    for (std::size_t i = 0; i < w.count; ++i) {
        if (w.inputs[i].role == r) return level_of(w.inputs[i], cycle);
    }
    return false;
}

BridgeState MotorDriverReader::state_at(std::size_t m, Cycles cycle) const {
    const Wheel& w = wheel_[m];
    plant::DriverInputLevels levels;
    for (std::size_t i = 0; i < w.count; ++i) levels.*(w.inputs[i].level) = level_of(w.inputs[i], cycle);
    return mirrored(plant::bridge_state(w.driver, levels), w.reversed);
}

Cycles MotorDriverReader::next_change_after(std::size_t m, Cycles cycle) const {
    const Wheel& w = wheel_[m];
    Cycles next = kNever;
    for (std::size_t i = 0; i < w.count; ++i) {
        const Input& in = w.inputs[i];
        if (in.signal != nullptr) {
            next = std::min(next, in.signal->next_change_after(cycle));
        } else if (!in.tied_high) {
            next = std::min(next, pins_.next_change_after(in.pin, cycle));
        }
    }
    return next;
}

plant::BridgeInput MotorDriverReader::input_at(std::size_t m, Cycles cycle) const {
    plant::BridgeInput b = averaged(m);
    b.state = state_at(m, cycle);
    return b;
}

plant::BridgeInput MotorDriverReader::averaged(std::size_t m) const {
    AveragedCache& cache = averaged_[m];
    if (cache.revision == revision(m)) return cache.input;
    cache.revision = revision(m);
    const Wheel& w = wheel_[m];
    plant::DriverInputDuties duties;
    for (std::size_t i = 0; i < w.count; ++i) duties.*(w.inputs[i].duty) = duty_of(w.inputs[i]);
    const plant::BridgeAverage avg = plant::average_bridge(w.driver, duties);
    plant::BridgeInput& b = cache.input;
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

uint64_t MotorDriverReader::revision(std::size_t m) const {
    uint64_t r = pins_.revision();
    const Wheel& w = wheel_[m];
    for (std::size_t i = 0; i < w.count; ++i) {
        if (w.inputs[i].signal != nullptr) r += w.inputs[i].signal->revision();
    }
    return r;
}

std::string MotorDriverReader::takeover_warning(std::size_t m, const Input& in, const PinWaveforms::Takeover& t) const {
    const std::string pin = sketch_pin_name(board_description(board_.model), in.pin);
    return fmt::format("pin {} ({}) is OC{}{} of Timer{}, which the firmware ran in {} mode (WGM {}) from {:.4f} s: "
                       "analogWrite({}) makes no PWM there (the Servo library takes Timer1 so on the Uno: D9, D10)",
                       pin, input_label(board_, m, in.role), t.timer, t.channel, t.timer, t.ctc ? "CTC" : "normal",
                       t.wgm, cycles_to_s(t.since, core_clock_hz_), pin);
}

std::vector<std::string> MotorDriverReader::wiring_warnings() const {
    std::vector<std::string> out;
    for (std::size_t m = 0; m < 2; ++m) {
        const Wheel& w = wheel_[m];
        for (std::size_t i = 0; i < w.count; ++i) {
            const Input& in = w.inputs[i];
            if (in.tied_high || in.signal != nullptr) continue;
            if (const auto t = pins_.takeover(in.pin)) out.push_back(takeover_warning(m, in, *t));
            if (pins_.ever_output(in.pin)) continue;
            const bool pullup = pins_.mode(in.pin) == PinMode::input_pullup;
            out.push_back(fmt::format("pin {} ({}) is never set as an output: the driver sees only {}",
                                      sketch_pin_name(board_description(board_.model), in.pin),
                                      input_label(board_, m, in.role),
                                      pullup ? "the pull-up (high)" : "a floating input (read as low)"));
        }
    }
    return out;
}

}  // namespace ddmr::hil
