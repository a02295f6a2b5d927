// The readers of a scenario's values (yaml_ctx.hpp).
#include "scenario/yaml_ctx.hpp"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <regex>
#include <vector>

namespace ddmr::tools::scenario::yaml {

/// A path written in the scenario: relative, inside the scenario's folder.
fs::path inside_folder(const Ctx& c) {
    const std::string text = c.str();
    const fs::path p(text);
    if (p.is_absolute()) {
        c.fail(fmt::format("'{}' is absolute: paths in a scenario are relative to its folder "
                           "(give other files on the command line)", text));
    }
    const fs::path folder = fs::absolute(c.file()).parent_path().lexically_normal();
    fs::path full = (folder / p).lexically_normal();  // not const: returned by move
    const auto rel = full.lexically_relative(folder);
    if (rel.empty() || *rel.begin() == "..") {
        c.fail(fmt::format("'{}' leaves the scenario's folder {}", text, folder.string()));
    }
    return full;
}

fs::path existing_file(const Ctx& c) {
    fs::path p = inside_folder(c);
    if (!fs::is_regular_file(p)) c.fail(fmt::format("file '{}' does not exist", p.string()));
    return p;
}

/// A digital pin of the scenario's board: its number, or its silkscreen name
/// as a board file takes it ("D22", "A8").
int board_pin(const Ctx& c) {
    const std::string text = c.str();
    if (!text.empty() && std::isdigit(static_cast<unsigned char>(text.front())) != 0) {
        return c.integer_in(0, c.board().pin_count() - 1);
    }
    const std::optional<int> pin = hil::parse_pin_name(c.board(), text);
    if (!pin) c.fail(fmt::format("'{}' is not a pin of the {} (pins {})", text, c.board().label, hil::pin_range(c.board())));
    return *pin;
}

/// A timer-output pin that drives a motor driver input of the wiring.
int pwm_pin(const Ctx& c) {
    const int pin = board_pin(c);
    if (!hil::board_pin(c.board(), pin)->oc) {
        c.fail(fmt::format("pin {} has no timer output (PWM pins: {})", pin, hil::pwm_pin_list(c.board())));
    }
    if (c.wiring() != nullptr) {
        std::vector<int> inputs;  // the wiring's driver inputs on timer pins
        for (const hil::WheelWiring& w : c.wiring()->wheel) {
            for (const hil::InputWire& in : w.motor.input) {
                if (in.on_pin() && hil::board_pin(c.board(), in.pin)->oc &&
                    std::find(inputs.begin(), inputs.end(), in.pin) == inputs.end()) {
                    inputs.push_back(in.pin);
                }
            }
        }
        if (std::find(inputs.begin(), inputs.end(), pin) == inputs.end()) {
            std::sort(inputs.begin(), inputs.end());
            c.fail(fmt::format("pin {} feeds no motor driver input of the board ({}); the driver inputs on timer "
                               "pins are {}",
                               pin, c.wiring()->source,
                               inputs.empty() ? std::string("none") : fmt::format("{}", fmt::join(inputs, ", "))));
        }
    }
    return pin;
}

CompareOp compare_op(const Ctx& c) {
    const std::string s = c.str();
    if (s == "==") return CompareOp::kEq;
    if (s == "!=") return CompareOp::kNe;
    if (s == "<") return CompareOp::kLt;
    if (s == "<=") return CompareOp::kLe;
    if (s == ">") return CompareOp::kGt;
    // cppcheck-suppress missingReturn ; the path ends in Ctx::fail, [[noreturn]] (it throws)
    if (s == ">=") return CompareOp::kGe;
    c.fail(fmt::format("'{}' is not one of ==, !=, <, <=, >, >=", s));
}

void check_regex(const Ctx& c, const std::string& pattern) {
    try {
        std::regex re(pattern, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
        c.fail(fmt::format("'{}' is not a valid regular expression: {}", pattern, e.what()));
    }
}

/// A wheel: 1 or `right` (motor 1), 2 or `left` (motor 2).
int wheel_number(const Ctx& c) {
    const std::string s = c.str();
    if (s == "right") return 1;
    if (s == "left") return 2;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    // cppcheck-suppress missingReturn ; the path ends in Ctx::fail, [[noreturn]] (it throws)
    if (!s.empty() && end == s.c_str() + s.size() && (v == 1.0 || v == 2.0)) return static_cast<int>(v);
    c.fail(fmt::format("'{}' is not a wheel (1 or right, 2 or left)", s));
}

Range min_max_pair(const Ctx& c) {
    if (!c.node().IsSequence() || c.node().size() != 2) c.fail("expected [min, max]");
    Range r;
    r.min = c.at(c.node()[0], c.key() + "[0]").number();
    r.max = c.at(c.node()[1], c.key() + "[1]").number();
    if (*r.min > *r.max) c.fail(fmt::format("min {} is above max {}", *r.min, *r.max));
    return r;
}

std::string plant_signal_name(const Ctx& c) {
    std::string s = c.str();
    if (is_plant_signal(s)) return s;
    const auto& world = world_signal_names();
    if (std::find(world.begin(), world.end(), s) != world.end()) return s;
    // NAME.COLUMN of a part on the board (its columns are checked when the
    // robot is built, before the run: they depend on the part's options).
    const std::size_t dot = s.find('.');
    if (const hil::BoardWiring* wiring = c.wiring(); wiring != nullptr && dot != std::string::npos) {
        const std::string part = s.substr(0, dot);
        for (const hil::PartEntry& p : wiring->parts) {
            if (p.name == part) return s;
        }
    }
    std::string list;
    for (const std::string& n : plant_signal_names()) list += (list.empty() ? "" : ", ") + n;
    for (const std::string& n : world) list += ", " + n;
    // cppcheck-suppress missingReturn ; Ctx::fail is [[noreturn]] (it throws)
    c.fail(fmt::format("'{}' is not a signal (one of {}, or a board part's truth column PART.COLUMN)", s, list));
}

std::optional<Cycles> optional_for(const Ctx& c) {
    if (!c.has("for")) return std::nullopt;
    return c.child("for").duration();
}

}  // namespace ddmr::tools::scenario::yaml
