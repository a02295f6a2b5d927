#include "hil/board.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <map>
#include <stdexcept>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

using namespace atmega328p;

constexpr int kUnoPinCount = 20;  ///< D0..D13 and A0..A5 (14..19)

std::string where(const YAML::Node& n, const std::string& source) {
    const YAML::Mark m = n.Mark();
    if (m.is_null()) return source;
    return source + ":" + std::to_string(m.line + 1) + ":" + std::to_string(m.column + 1);
}

int read_pin(const YAML::Node& n, const std::string& key, const std::string& source) {
    if (!n.IsScalar()) {
        throw std::runtime_error(where(n, source) + ": board." + key + " must be a pin number");
    }
    try {
        return n.as<int>();
    } catch (const YAML::Exception&) {
        throw std::runtime_error(where(n, source) + ": board." + key + " = '" + n.Scalar() +
                                 "' is not an integer pin number");
    }
}

}  // namespace

std::optional<PinLocation> uno_pin_location(int pin) {
    if (pin < 0 || pin >= kUnoPinCount) return std::nullopt;
    if (pin <= 7) return PinLocation{'D', pin, reg::kPortD};
    if (pin <= 13) return PinLocation{'B', pin - 8, reg::kPortB};
    return PinLocation{'C', pin - 14, reg::kPortC};
}

std::optional<PwmChannel> uno_pwm_channel(int pin) {
    switch (pin) {
        case 9: return PwmChannel{"OC1A", 1, reg::kTccr1A, com_bit::kComA1, reg::kTccr1B, reg::kOcr1AL, reg::kOcr1AH};
        case 10: return PwmChannel{"OC1B", 1, reg::kTccr1A, com_bit::kComB1, reg::kTccr1B, reg::kOcr1BL, reg::kOcr1BH};
        case 11: return PwmChannel{"OC2A", 2, reg::kTccr2A, com_bit::kComA1, reg::kTccr2B, reg::kOcr2A, 0};
        case 3: return PwmChannel{"OC2B", 2, reg::kTccr2A, com_bit::kComB1, reg::kTccr2B, reg::kOcr2B, 0};
        default: return std::nullopt;
    }
}

std::optional<int> uno_external_interrupt(int pin) {
    if (pin == 2) return 0;
    if (pin == 3) return 1;
    return std::nullopt;
}

BoardWiring uno_default_board() {
    BoardWiring b;
    b.motor[0] = MotorWiring{10, 12};
    b.motor[1] = MotorWiring{11, 13};
    b.encoder[0] = EncoderWiring{2};
    b.encoder[1] = EncoderWiring{3};
    return b;
}

void validate(const BoardWiring& board, const std::string& source) {
    std::map<int, std::string> used;
    const auto claim = [&](int pin, const std::string& key) {
        if (!uno_pin_location(pin)) {
            throw std::invalid_argument(source + ": board." + key + " = " + std::to_string(pin) +
                                        ": the Uno has pins 0 to 19 (A0..A5 = 14..19)");
        }
        if (pin == 0 || pin == 1) {
            throw std::invalid_argument(source + ": board." + key + " = " + std::to_string(pin) +
                                        ": pins 0 and 1 carry the UART (RX, TX)");
        }
        const auto [it, fresh] = used.emplace(pin, key);
        if (!fresh) {
            throw std::invalid_argument(source + ": board." + key + " = " + std::to_string(pin) +
                                        ": pin already used by board." + it->second);
        }
    };
    for (std::size_t m = 0; m < board.motor.size(); ++m) {
        const std::string motor = "motor" + std::to_string(m + 1);
        claim(board.motor[m].enable_pin, motor + ".enable_pin");
        if (!uno_pwm_channel(board.motor[m].enable_pin)) {
            throw std::invalid_argument(fmt::format("{}: board.{}.enable_pin = {}: not a phase-correct PWM pin "
                                                    "(3, 9, 10 or 11)",
                                                    source, motor, board.motor[m].enable_pin));
        }
        claim(board.motor[m].direction_pin, motor + ".direction_pin");
    }
    for (std::size_t e = 0; e < board.encoder.size(); ++e) {
        claim(board.encoder[e].pin, "encoder" + std::to_string(e + 1) + ".pin");
    }
}

std::optional<BoardWiring> load_board_section(const std::filesystem::path& path) {
    const std::string source = path.string();
    YAML::Node root;
    try {
        root = YAML::LoadFile(source);
    } catch (const YAML::BadFile&) {
        throw std::runtime_error(source + ": cannot read the board file");
    } catch (const YAML::ParserException& e) {
        throw std::runtime_error(source + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
    }
    if (!root.IsMap() || !root["board"]) return std::nullopt;
    const YAML::Node section = root["board"];
    if (!section.IsMap()) throw std::runtime_error(where(section, source) + ": board must be a mapping");
    BoardWiring board = uno_default_board();
    for (const auto& kv : section) {
        const std::string part = kv.first.as<std::string>();
        const YAML::Node& body = kv.second;
        int index = -1;
        bool is_motor = false;
        if (part == "motor1" || part == "motor2") {
            is_motor = true;
            index = part.back() - '1';
        } else if (part == "encoder1" || part == "encoder2") {
            index = part.back() - '1';
        } else {
            throw std::runtime_error(where(kv.first, source) + ": unknown key board." + part +
                                     " (expected motor1, motor2, encoder1, encoder2)");
        }
        if (!body.IsMap()) throw std::runtime_error(where(body, source) + ": board." + part + " must be a mapping");
        const auto i = static_cast<std::size_t>(index);
        for (const auto& field : body) {
            const std::string key = field.first.as<std::string>();
            const std::string full = fmt::format("{}.{}", part, key);
            if (is_motor && key == "enable_pin") {
                board.motor[i].enable_pin = read_pin(field.second, full, source);
            } else if (is_motor && key == "direction_pin") {
                board.motor[i].direction_pin = read_pin(field.second, full, source);
            } else if (!is_motor && key == "pin") {
                board.encoder[i].pin = read_pin(field.second, full, source);
            } else {
                throw std::runtime_error(where(field.first, source) + ": unknown key board." + full);
            }
        }
    }
    try {
        validate(board, where(section, source));
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    return board;
}

}  // namespace ddmr::hil
