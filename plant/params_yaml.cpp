#include "plant/params_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <type_traits>
#include <variant>

namespace ddmr::plant {

namespace {

std::string where(const std::string& source, const YAML::Mark& mark) {
    std::ostringstream os;
    os << source;
    if (mark.line >= 0) os << ':' << (mark.line + 1) << ':' << (mark.column + 1);
    return os.str();
}

std::string scalar_text(const YAML::Node& node) {
    if (node.IsScalar()) return node.Scalar();
    if (node.IsNull()) return "";
    return node.IsSequence() ? "<sequence>" : "<mapping>";
}

template <class T>
bool convert_scalar(const YAML::Node& node, T& out) {
    if (!node.IsScalar()) return false;
    return YAML::convert<T>::decode(node, out);
}

/// Two keys of a part that stand for one another (the encoders' resolution:
/// edges_per_motor_rev or edges_per_wheel_rev, 0 = not given). A section
/// may give one of them; it then replaces the other one's default.
template <class P>
std::array<const char*, 2> alternative_keys() {
    return {nullptr, nullptr};
}
template <>
std::array<const char*, 2> alternative_keys<HallEncoderParams>() {
    return {"edges_per_motor_rev", "edges_per_wheel_rev"};
}

bool is_key(const char* alternative, const std::string& key) {
    return alternative != nullptr && key == alternative;
}

/// Sets the field `key` of `part` to 0 ("not given").
template <class P, std::size_t N>
void clear_field(P& part, const std::array<Field<P>, N>& table, const char* key) {
    for (const Field<P>& f : table) {
        if (std::string_view(f.key) != key) continue;
        std::visit([&](auto m) { part.*m = {}; }, f.member);
    }
}

/// Reads one key of a section into `part`, checking it against `table`.
template <class P, std::size_t N>
void read_key(const std::string& key, const YAML::Node& key_node, const YAML::Node& value,
              const std::string& section, P& part, const std::array<Field<P>, N>& table,
              const std::string& source) {
    std::string name = section;
    name.append(".").append(key);
    const Field<P>* field = nullptr;
    for (const Field<P>& f : table) {
        if (key == f.key) field = &f;
    }
    if (field == nullptr) {
        throw ParamsFileError(where(source, key_node.Mark()) + ": unknown key '" + name + "'");
    }
    const std::string text = scalar_text(value);
    std::string at = where(source, value.Mark());
    at.append(": ").append(name).append(": invalid value '").append(text).append("'");
    bool ok = false;
    std::visit(
        [&](auto m) {
            using T = std::decay_t<decltype(part.*m)>;
            T v{};
            ok = convert_scalar(value, v);
            if (ok) part.*m = v;
        },
        field->member);
    if (!ok) {
        const bool integer = !std::holds_alternative<double P::*>(field->member);
        throw ParamsFileError(at + (integer ? ": not an integer" : ": not a number") + " [" +
                              field->unit + "]");
    }
    if (!std::holds_alternative<std::uint64_t P::*>(field->member) &&
        !field->range.contains(field_value(part, *field))) {
        throw ParamsFileError(at + ": must be finite and in " + field->range.text() + " " +
                              field->unit);
    }
    try {
        validate(part, section.c_str());  // constraints beyond the range (e.g. even)
    } catch (const std::invalid_argument& e) {
        throw ParamsFileError(at + ": " + e.what());
    }
}

/// Reads one section's mapping into `part`, checking each key against `table`.
template <class P, std::size_t N>
void read_section(const YAML::Node& map, const std::string& section, P& part,
                  const std::array<Field<P>, N>& table, const std::string& source) {
    if (!map.IsMap()) {
        throw ParamsFileError(where(source, map.Mark()) + ": " + section +
                              ": expected a mapping of parameter keys, got '" +
                              scalar_text(map) + "'");
    }
    const std::array<const char*, 2> alt = alternative_keys<P>();
    std::array<bool, 2> given{};
    std::array<YAML::Mark, 2> mark{};
    for (const auto& kv : map) {
        const std::string key = kv.first.as<std::string>();
        for (std::size_t j = 0; j < alt.size(); ++j) {
            if (!is_key(alt[j], key)) continue;
            given[j] = true;
            mark[j] = kv.first.Mark();
        }
    }
    if (given[0] && given[1]) {
        const YAML::Mark& later = mark[0].line < mark[1].line ? mark[1] : mark[0];
        throw ParamsFileError(where(source, later) + ": " + section + "." + alt[0] + " (line " +
                              std::to_string(mark[0].line + 1) + ") and " + section + "." +
                              alt[1] + " (line " + std::to_string(mark[1].line + 1) +
                              ") are alternatives: give only one of them");
    }
    for (std::size_t j = 0; j < alt.size(); ++j) {
        if (given[j]) clear_field(part, table, alt[1 - j]);
    }
    // The alternative key first: with the other one cleared, the section is
    // consistent again (and validated) only once it is read.
    for (const bool alternatives : {true, false}) {
        for (const auto& kv : map) {
            const std::string key = kv.first.as<std::string>();
            if ((is_key(alt[0], key) || is_key(alt[1], key)) != alternatives) continue;
            read_key(key, kv.first, kv.second, section, part, table, source);
        }
    }
}

}  // namespace

RobotParams parse_robot_params(std::string_view yaml_text, const std::string& source) {
    YAML::Node root;
    try {
        root = YAML::Load(std::string(yaml_text));
    } catch (const YAML::Exception& e) {
        throw ParamsFileError(where(source, e.mark) + ": malformed YAML: " + e.msg);
    }
    RobotParams p = default_robot_params();
    if (root.IsNull()) return p;  // an empty file: all defaults
    if (!root.IsMap()) {
        throw ParamsFileError(where(source, root.Mark()) +
                              ": expected a mapping of sections (motor1, motor2, driver, ...)");
    }
    for (const auto& kv : root) {
        const std::string section = kv.first.as<std::string>();
        if (section == kBoardSection) {
            throw ParamsFileError(where(source, kv.first.Mark()) +
                                  ": key 'board': the wiring is no longer part of the plant file; write it in "
                                  "a board file and pass it with --board (docs/boards.md)");
        }
        bool known = false;
        for_each_section(p, [&](const char* name, auto& part, const auto& table) {
            if (section != name) return;
            known = true;
            read_section(kv.second, section, part, table, source);
        });
        if (!known) {
            throw ParamsFileError(where(source, kv.first.Mark()) + ": unknown key '" + section +
                                  "' (sections: motor1, motor2, driver, tb6612, drv8833, l293d, l9110, "
                                  "battery, encoder1, encoder2, kinematics, integration)");
        }
    }
    try {
        validate(p);
    } catch (const std::invalid_argument& e) {
        throw ParamsFileError(source + ": " + e.what());
    }
    return p;
}

RobotParams load_robot_params(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw ParamsFileError(path.string() + ": cannot read plant parameter file: " +
                              std::strerror(errno));
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parse_robot_params(text.str(), path.string());
}

std::string emit_robot_params(const RobotParams& p) {
    YAML::Emitter out;
    out.SetDoublePrecision(17);
    out << YAML::BeginMap;
    for_each_section(p, [&](const char* name, const auto& part, const auto& table) {
        using P = std::decay_t<decltype(part)>;
        const std::array<const char*, 2> alt = alternative_keys<P>();
        out << YAML::Key << name << YAML::Value << YAML::BeginMap;
        for (const auto& f : table) {
            // Of two alternative keys only the one given (> 0) is written.
            const bool alternative = is_key(alt[0], f.key) || is_key(alt[1], f.key);
            if (alternative && field_value(part, f) == 0.0) continue;
            out << YAML::Key << f.key << YAML::Value;
            std::visit([&](auto m) { out << part.*m; }, f.member);
        }
        out << YAML::EndMap;
    });
    out << YAML::EndMap;
    return std::string(out.c_str()) + "\n";
}

void save_robot_params(const RobotParams& p, const std::filesystem::path& path) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << emit_robot_params(p);
    out.flush();
    if (!out) {
        throw ParamsFileError(path.string() + ": cannot write plant parameter file: " +
                              std::strerror(errno));
    }
}

}  // namespace ddmr::plant
