#include "hil/board.hpp"
#include "hil/parts/part_entries.hpp"
#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "hil/yaml_reader.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <map>
#include <set>
#include <stdexcept>


namespace ddmr::hil {
namespace {

using plant::DriverType;

/// The motor driver part types (hil/parts/driver_*.cpp), in the registry's order.
std::vector<const PartType*> driver_types() {
    std::vector<const PartType*> out;
    for (const PartType* t : PartRegistry::global().types()) {
        if (t->motor_driver) out.push_back(t);
    }
    return out;
}

/// "dir-pwm, l298n, tb6612, drv8833, l293d or l9110".
std::string driver_key_list() {
    std::string out;
    const auto types = driver_types();
    for (std::size_t i = 0; i < types.size(); ++i) {
        out += i == 0 ? "" : (i + 1 == types.size() ? " or " : ", ");
        out += types[i]->type;
    }
    return out;
}

const PartType& driver_type_of(DriverType t) {
    for (const PartType* type : driver_types()) {
        if (type->motor_driver->type == t) return *type;
    }
    throw std::logic_error("no part type for this driver");
}

const MotorDriverSpec& spec_of(DriverType t) { return *driver_type_of(t).motor_driver; }

bool contains(const std::vector<DriverRole>& v, DriverRole r) { return std::find(v.begin(), v.end(), r) != v.end(); }

constexpr std::array<DriverRole, kDriverRoleCount> kAllRoles = {DriverRole::pwm, DriverRole::dir,  DriverRole::en,
                                                               DriverRole::in1, DriverRole::in2, DriverRole::stby,
                                                               DriverRole::sleep};

[[noreturn]] void fail(const std::string& source, int line, const std::string& key, const std::string& what) {
    throw std::invalid_argument(fmt::format("{}: key '{}': {}", file_line(source, line), key, what));
}

/// The board-file key of wheel m's driver input r: wheels.W.motor.R, or parts.NAME.R.
std::string motor_key(const BoardWiring& b, std::size_t m, DriverRole r) {
    const std::string& at = b.wheel[m].motor.key;
    return fmt::format("{}.{}", at.empty() ? fmt::format("wheels.{}.motor", wheel_name(m)) : at, role_key(r));
}

std::string encoder_key(const EncoderWiring& e, std::size_t m, unsigned s) {
    return fmt::format("{}.{}", e.key.empty() ? fmt::format("wheels.{}.encoder", wheel_name(m)) : e.key,
                       encoder_signal_key(e, s));
}

/// The console USART's pins (0 and 1) carry Serial, the USB serial port.
void check_pin(const BoardDescription& desc, const std::string& source, int line, const std::string& key, int pin) {
    if (!board_pin(desc, pin)) {
        fail(source, line, key, fmt::format("the {} has no pin {} (pins {})", desc.label, pin, pin_range(desc)));
    }
    for (const auto& [at, name] : {std::pair{desc.console().rxd, "RX"}, std::pair{desc.console().txd, "TX"}}) {
        if (pin_number_of(desc, at) == pin) {
            fail(source, line, key,
                 fmt::format("pin {} carries Serial's {} (pins 0 and 1, the USB serial port, cannot be wired)", pin,
                             name));
        }
    }
}

}  // namespace

const char* role_key(DriverRole r) {
    switch (r) {
        case DriverRole::pwm: return "PWM";
        case DriverRole::dir: return "DIR";
        case DriverRole::en: return "EN";
        case DriverRole::in1: return "IN1";
        case DriverRole::in2: return "IN2";
        case DriverRole::stby: return "STBY";
        case DriverRole::sleep: return "SLEEP";
    }
    return "?";
}

const char* wheel_name(std::size_t m) { return m == 0 ? "right" : "left"; }

const char* driver_key(DriverType t) { return driver_type_of(t).type.c_str(); }
const char* driver_label(DriverType t) { return spec_of(t).label.c_str(); }

std::string input_label(const BoardWiring& b, std::size_t m, DriverRole r) {
    return fmt::format("{} {} {}", wheel_name(m), driver_label(b.wheel[m].motor.driver), role_key(r));
}

const char* encoder_signal_key(const EncoderWiring& e, unsigned signal) {
    if (e.kind != EncoderKind::quadrature) return "OUT";
    return signal == 0 ? "A" : "B";
}

BoardWiring default_board() {
    BoardWiring b;
    const std::array<std::array<int, 3>, 2> pins = {{{10, 12, 2}, {11, 13, 3}}};  // PWM, DIR, encoder
    for (std::size_t m = 0; m < 2; ++m) {
        MotorWiring& w = b.wheel[m].motor;
        w.driver = DriverType::dir_pwm;
        w[DriverRole::pwm] = InputWire{true, false, pins[m][0], 0, {}};
        w[DriverRole::dir] = InputWire{true, false, pins[m][1], 0, {}};
        b.wheel[m].encoder.kind = EncoderKind::single;
        b.wheel[m].encoder.pin = {pins[m][2], -1};
    }
    return b;
}

namespace {

/// Each wheel input a part drives names a part and port that exist; the parts'
/// own inputs too, without a loop (part_order).
void check_part_feeds(const BoardWiring& board) {
    const PartRegistry& registry = PartRegistry::global();
    for (std::size_t m = 0; m < 2; ++m) {
        for (const DriverRole r : kAllRoles) {
            const InputWire& in = board.wheel[m].motor[r];
            if (in.part_output.empty()) continue;
            const auto ref = parse_part_output_ref(in.part_output);
            const auto part = std::find_if(board.parts.begin(), board.parts.end(),
                                           [&](const PartEntry& p) { return p.name == ref->part; });
            if (part == board.parts.end()) {
                fail(board.source, in.line, motor_key(board, m, r),
                     fmt::format("'{}': no part is called '{}': the input is fed by nothing", in.part_output, ref->part));
            }
            const PartType* type = registry.find(part->type);
            if (type == nullptr || !type->has_port(ref->port)) {
                fail(board.source, in.line, motor_key(board, m, r),
                     fmt::format("'{}': part '{}' ({}) has no output '{}': the input is fed by nothing", in.part_output,
                                 ref->part, part->type, ref->port));
            }
        }
    }
    (void)part_order(board.parts, registry, board.source);
}

}  // namespace

void validate(const BoardWiring& board) {
    const std::string& src = board.source;
    const BoardDescription& desc = board_description(board.model);
    struct Use {
        std::string key;
        std::size_t wheel;
        DriverRole role;
        bool shareable;
    };
    std::map<int, Use> used;
    const auto claim = [&](int pin, int line, const Use& u) {
        check_pin(desc, src, line, u.key, pin);
        const auto [it, fresh] = used.emplace(pin, u);
        if (fresh) return;
        const Use& first = it->second;
        // One TB6612 / DRV8833 module drives both motors through one STBY / nSLEEP pin.
        const bool same_module = u.shareable && first.shareable && first.role == u.role && first.wheel != u.wheel &&
                                 board.wheel[0].motor.driver == board.wheel[1].motor.driver;
        if (!same_module) fail(src, line, u.key, fmt::format("pin {} is already used by {}", pin, first.key));
    };
    for (std::size_t m = 0; m < 2; ++m) {
        const MotorWiring& w = board.wheel[m].motor;
        const MotorDriverSpec& spec = spec_of(w.driver);
        for (const DriverRole r : kAllRoles) {
            const InputWire& in = w[r];
            if (!in.on_pin()) continue;
            claim(in.pin, in.line, Use{motor_key(board, m, r), m, r, contains(spec.shared, r)});
            if (contains(spec.pwm_only, r) && !board_pin(desc, in.pin)->oc) {
                fail(src, in.line, motor_key(board, m, r),
                     fmt::format("pin {} has no timer output, so analogWrite gives only LOW or HIGH there; the "
                                 "PWM pins are {}",
                                 in.pin, pwm_pin_list(desc)));
            }
        }
    }
    for (std::size_t m = 0; m < 2; ++m) {
        const EncoderWiring& e = board.wheel[m].encoder;
        for (unsigned s = 0; s < e.signals(); ++s) {
            claim(e.pin[s], e.line[s], Use{encoder_key(e, m, s), m, DriverRole::pwm, false});
        }
    }
    // Parts: a pin a part drives is used once; parts' inputs may share a pin
    // (two 74HC595s on one clock), not with anything else.
    std::map<int, std::string> part_inputs;
    for (const PartEntry& p : board.parts) {
        const PartType* type = PartRegistry::global().find(p.type);
        if (type == nullptr) fail(src, p.line, "parts." + p.name + ".type", fmt::format("unknown part type '{}'", p.type));
        for (const auto& [k, v] : p.values) {
            if (v.pin < 0) continue;
            const std::string key = fmt::format("parts.{}.{}", p.name, k);
            if (type->key(k)->kind != PartKeyKind::input) {
                if (const auto it = part_inputs.find(v.pin); it != part_inputs.end()) {
                    fail(src, v.line, key, fmt::format("pin {} is already used by {}", v.pin, it->second));
                }
                claim(v.pin, v.line, Use{key, 2, DriverRole::pwm, false});
                continue;
            }
            check_pin(desc, src, v.line, key, v.pin);
            if (const auto it = used.find(v.pin); it != used.end()) {
                fail(src, v.line, key, fmt::format("pin {} is already used by {}", v.pin, it->second.key));
            }
            part_inputs.emplace(v.pin, key);
        }
    }
    check_part_feeds(board);
}

std::map<int, std::string> pin_uses(const BoardWiring& board) {
    std::map<int, std::string> uses;  // the first use of a shared pin names it
    for (std::size_t m = 0; m < 2; ++m) {
        const WheelWiring& w = board.wheel[m];
        for (const DriverRole r : kAllRoles) {
            if (w.motor[r].on_pin()) uses.emplace(w.motor[r].pin, motor_key(board, m, r));
        }
        for (unsigned s = 0; s < w.encoder.signals(); ++s) uses.emplace(w.encoder.pin[s], encoder_key(w.encoder, m, s));
    }
    for (const PartEntry& p : board.parts) {
        for (const auto& [key, v] : p.values) {
            if (v.pin >= 0) uses.emplace(v.pin, fmt::format("parts.{}.{}", p.name, key));
        }
    }
    return uses;
}

std::vector<int> wired_pins(const BoardWiring& board) {
    std::vector<int> pins;
    for (const auto& [pin, key] : pin_uses(board)) pins.push_back(pin);
    return pins;
}

void check_host_serial_pins(const BoardWiring& board, const UsartDesc& usart) {
    const BoardDescription& desc = board_description(board.model);
    const std::string port = serial_port_name(usart.index);
    const auto check = [&](int pin, int line, const std::string& key) {
        for (const auto& [at, name] : {std::pair{usart.rxd, "RX"}, std::pair{usart.txd, "TX"}}) {
            if (pin_number_of(desc, at) == pin) {
                fail(board.source, line, key,
                     fmt::format("pin {} carries {}'s {}; the host serial adapter is on {}", pin, port, name, port));
            }
        }
    };
    for (std::size_t m = 0; m < 2; ++m) {
        for (const DriverRole r : kAllRoles) {
            const InputWire& in = board.wheel[m].motor[r];
            if (in.on_pin()) check(in.pin, in.line, motor_key(board, m, r));
        }
        const EncoderWiring& e = board.wheel[m].encoder;
        for (unsigned s = 0; s < e.signals(); ++s) check(e.pin[s], e.line[s], encoder_key(e, m, s));
    }
    for (const PartEntry& p : board.parts) {
        for (const auto& [k, v] : p.values) {
            if (v.pin >= 0) check(v.pin, v.line, fmt::format("parts.{}.{}", p.name, k));
        }
    }
}

// --- the file ----------------------------------------------------------------

namespace {

struct Reader : YamlReader {
    const BoardDescription* desc = &board_description(BoardModel::uno);

    int pin(const YAML::Node& n, const std::string& key) const {
        if (!n.IsScalar()) fail(n, key, fmt::format("expected a pin: {}", pin_range(*desc)));
        const auto p = parse_pin_name(*desc, n.Scalar());
        if (!p) {
            const std::string& s = n.Scalar();
            for (const char* analog : desc->analog_only) {
                if (s == analog) {
                    fail(n, key, fmt::format("{} is an analog-only input of the {} (no port bit), not a digital pin",
                                             s, desc->label));
                }
            }
            fail(n, key, fmt::format("'{}' is not a pin of the {} (pins {}, or {}..{})", s, desc->label,
                                     pin_range(*desc), desc->analog0, desc->pin_count() - 1));
        }
        return *p;
    }
    /// `wheels.W.motor`: {driver: TYPE, <its inputs>, reversed}.
    MotorWiring motor(const YAML::Node& n, const std::string& key) const {
        mapping(n, key);
        if (!n["driver"]) fail(n, key + ".driver", fmt::format("missing ({})", driver_key_list()));
        const std::string type = n["driver"].Scalar();
        const PartType* part = PartRegistry::global().find(type);
        if (part == nullptr || !part->motor_driver) {
            fail(n["driver"], key + ".driver", fmt::format("unknown driver '{}' ({})", type, driver_key_list()));
        }
        return motor_inputs(n, key, *part->motor_driver, {"driver", "reversed"});
    }
    /// A driver's inputs by role, and `reversed`, from mapping `n` (whose other keys are `allowed`).
    MotorWiring motor_inputs(const YAML::Node& n, const std::string& key, const MotorDriverSpec& s,
                             std::vector<std::string> allowed) const {
        const MotorDriverSpec* spec = &s;
        MotorWiring w;
        w.driver = spec->type;
        for (const DriverRole r : spec->required) allowed.emplace_back(role_key(r));
        for (const DriverRole r : spec->optional_high) allowed.emplace_back(role_key(r));
        only_keys(n, key, allowed);
        if (n["reversed"]) w.reversed = boolean(n["reversed"], key + ".reversed");
        for (const DriverRole r : kAllRoles) {
            const bool required = contains(spec->required, r);
            const bool optional = contains(spec->optional_high, r);
            if (!required && !optional) continue;
            InputWire& in = w[r];
            in.used = true;
            const std::string k = key + "." + role_key(r);
            const YAML::Node v = n[role_key(r)];
            if (!v) {
                if (required) {
                    fail(n, k, fmt::format("missing: the {} input {} needs a pin{}", spec->label, role_key(r),
                                           contains(spec->may_be_high, r) ? " or high" : ""));
                }
                in.tied_high = true;  // nSLEEP: breakout boards pull it up
                continue;
            }
            in.line = line(v);
            if (v.IsScalar() && (v.Scalar() == "high" || v.Scalar() == "HIGH")) {
                if (!contains(spec->may_be_high, r)) {
                    fail(v, k, fmt::format("the {} input {} must be wired to a pin, not high", spec->label, role_key(r)));
                }
                in.tied_high = true;
                continue;
            }
            if (v.IsScalar() && parse_part_output_ref(v.Scalar())) {
                if (contains(spec->pwm_only, r)) {
                    fail(v, k, fmt::format("the {} input {} needs a timer's PWM: wire it to a PWM pin, not a part's "
                                           "output", spec->label, role_key(r)));
                }
                in.part_output = v.Scalar();
                continue;
            }
            in.pin = pin(v, k);
        }
        return w;
    }

    /// `wheels.W.encoder`: {type: TYPE, <its outputs>, reversed}.
    EncoderWiring encoder(const YAML::Node& n, const std::string& key) const {
        mapping(n, key);
        if (!n["type"]) fail(n, key + ".type", "missing (single or quadrature)");
        const std::string type = n["type"].Scalar();
        const PartType* part = PartRegistry::global().find(type);
        if (part == nullptr || !part->encoder) {
            fail(n["type"], key + ".type", fmt::format("unknown encoder type '{}' (single or quadrature)", type));
        }
        return encoder_pins(n, key, *part->encoder, {"type", "reversed"});
    }
    /// An encoder's output pins and `reversed` from mapping `n` (whose other keys are `allowed`).
    EncoderWiring encoder_pins(const YAML::Node& n, const std::string& key, const EncoderSpec& spec,
                               std::vector<std::string> allowed) const {
        EncoderWiring e;
        e.kind = spec.kind;
        for (const std::string& signal : spec.signals) allowed.push_back(signal);
        only_keys(n, key, allowed);
        if (n["reversed"]) e.reversed = boolean(n["reversed"], key + ".reversed");
        for (unsigned s = 0; s < e.signals(); ++s) {
            const char* name = encoder_signal_key(e, s);
            const YAML::Node v = n[name];
            if (!v) fail(n, key + "." + name, "missing: the encoder's output pin");
            e.pin[s] = pin(v, key + "." + name);
            e.line[s] = line(v);
        }
        return e;
    }
};

/// Where each wheel's driver and encoder came from: a parts: entry's key, or empty.
struct WheelSources {
    std::array<std::string, 2> motor, encoder;
};

/// The parts: list: a driver or an encoder with `wheel:` goes on its wheel,
/// any other part into b.parts.
void read_parts(const Reader& r, const YAML::Node& list, BoardWiring& b, WheelSources& from) {
    const PartRegistry& registry = PartRegistry::global();
    std::vector<PartEntry> entries = read_part_entries(
        r, list, [&r](const YAML::Node& n, const std::string& key) { return r.pin(n, key); }, registry, *r.desc);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const PartType& type = *registry.find(entries[i].type);
        if (!type.on_wheel()) {
            b.parts.push_back(std::move(entries[i]));
            continue;
        }
        const std::size_t m = entries[i].values.at("wheel").text == "right" ? 0 : 1;
        const std::string key = "parts." + entries[i].name;
        std::string& source = type.motor_driver ? from.motor[m] : from.encoder[m];
        if (!source.empty()) {
            r.fail(list[i]["wheel"], key + ".wheel",
                   fmt::format("the {} wheel's {} is given twice (also {})", wheel_name(m),
                               type.motor_driver ? "motor driver" : "encoder", source));
        }
        source = key;
        const std::vector<std::string> allowed = {"name", "type", "wheel", "reversed"};
        if (type.motor_driver) {
            b.wheel[m].motor = r.motor_inputs(list[i], key, *type.motor_driver, allowed);
            b.wheel[m].motor.key = key;
        } else {
            b.wheel[m].encoder = r.encoder_pins(list[i], key, *type.encoder, allowed);
            b.wheel[m].encoder.key = key;
        }
    }
}

/// The wheels: shorthand, for what the parts: list did not give: each wheel
/// needs a motor driver; a wheel with no encoder has none.
void read_wheels(const Reader& r, const YAML::Node& root, BoardWiring& b, const WheelSources& from) {
    const bool parts_drive_both = !from.motor[0].empty() && !from.motor[1].empty();
    if (!root["wheels"]) {
        if (!parts_drive_both) r.fail(root, "wheels", "missing: the left and right wheels' motor and encoder wiring");
        for (std::size_t m = 0; m < 2; ++m) {
            if (from.encoder[m].empty()) b.wheel[m].encoder.kind = EncoderKind::none;
        }
        return;
    }
    const YAML::Node wheels = r.mapping(root["wheels"], "wheels");
    r.only_keys(wheels, "wheels", {"left", "right"});
    for (std::size_t m = 0; m < 2; ++m) {
        const std::string key = fmt::format("wheels.{}", wheel_name(m));
        const YAML::Node w = wheels[wheel_name(m)];
        const bool listed = static_cast<bool>(w);
        if (!listed && from.motor[m].empty()) r.fail(wheels, key, "missing: both wheels must be described");
        if (listed) {
            r.mapping(w, key);
            r.only_keys(w, key, {"motor", "encoder"});
        }
        const bool motor = listed && w["motor"];
        if (motor && !from.motor[m].empty()) {
            r.fail(w["motor"], key + ".motor", fmt::format("given twice: {} is this wheel's motor driver", from.motor[m]));
        }
        if (!motor && from.motor[m].empty()) r.fail(w, key + ".motor", "missing");
        if (motor) b.wheel[m].motor = r.motor(w["motor"], key + ".motor");
        const bool encoder = listed && w["encoder"];
        if (encoder && !from.encoder[m].empty()) {
            r.fail(w["encoder"], key + ".encoder", fmt::format("given twice: {} is this wheel's encoder", from.encoder[m]));
        }
        if (encoder) {
            b.wheel[m].encoder = r.encoder(w["encoder"], key + ".encoder");
        } else if (from.encoder[m].empty()) {
            b.wheel[m].encoder.kind = EncoderKind::none;  // a robot without encoders
        }
    }
}

}  // namespace

BoardWiring load_board_file(const std::filesystem::path& path) {
    const std::string source = path.string();
    const YAML::Node root = YamlReader::load(path, "the board file");
    Reader r{{source}};
    if (!root.IsMap()) r.fail(root, "board", "a board file is a mapping with the keys board and wheels");
    r.only_keys(root, "", {"board", "parts", "wheels"});
    BoardWiring b;
    b.source = source;
    if (root["board"]) {
        const YAML::Node n = root["board"];
        if (n.IsMap()) {
            r.fail(n, "board", "the old wiring format (motor1/enable_pin, ...) is gone: write board: uno and a "
                               "wheels: section (docs/boards.md)");
        }
        const auto model = parse_board_key(n.Scalar());
        if (!model) r.fail(n, "board", fmt::format("unknown board '{}' ({})", n.Scalar(), board_key_list()));
        b.model = *model;
        r.desc = &board_description(b.model);
    }
    WheelSources from;
    if (root["parts"]) read_parts(r, root["parts"], b, from);
    read_wheels(r, root, b, from);
    try {
        validate(b);
    } catch (const std::invalid_argument& e) {
        throw std::runtime_error(e.what());
    }
    return b;
}

}  // namespace ddmr::hil
