#include "hil/parts/part_entries.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "hil/parts/part_set.hpp"

namespace ddmr::hil {
namespace {

bool is_name(const std::string& s) {
    return !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) != 0 || s[0] == '_') &&
           std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_' || c == '-'; });
}

std::string choice_list(const std::vector<std::string>& choices) {
    std::string out;
    for (const std::string& c : choices) out += (out.empty() ? "" : ", ") + c;
    return out;
}

PartEntry::Value read_value(const YamlReader& r, const YAML::Node& v, const std::string& key, const PartKey& spec,
                            const PinReader& pin) {
    PartEntry::Value out;
    out.line = r.line(v);
    out.text = r.text(v, key);
    switch (spec.kind) {
        case PartKeyKind::input:
            if (out.text == "HIGH" || out.text == "LOW") out.text = out.text == "HIGH" ? "high" : "low";
            if (out.text == "high" || out.text == "low" || parse_part_output_ref(out.text)) return out;
            out.pin = pin(v, key);
            return out;
        case PartKeyKind::output_pin:
            out.pin = pin(v, key);
            return out;
        case PartKeyKind::carrier:
            if (!is_name(out.text)) r.fail(v, key, fmt::format("'{}' is not a part's name", out.text));
            return out;
        case PartKeyKind::option:
            if (!spec.choices.empty()) {
                if (std::find(spec.choices.begin(), spec.choices.end(), out.text) == spec.choices.end()) {
                    r.fail(v, key, fmt::format("'{}' is not one of {}", out.text, choice_list(spec.choices)));
                }
                return out;
            }
            out.text = fmt::format("{}", r.number(v, key, spec.lo, spec.hi));
            return out;
    }
    return out;
}

PartEntry read_entry(const YamlReader& r, const YAML::Node& n, std::size_t index, const PinReader& pin,
                     const PartRegistry& registry, const BoardDescription& board) {
    const std::string at = fmt::format("parts[{}]", index);
    r.mapping(n, at);
    if (!n["name"]) r.fail(n, at + ".name", "missing: each part needs a name (other parts and the wheels say NAME.PORT)");
    PartEntry e;
    e.name = r.text(n["name"], at + ".name");
    e.line = r.line(n);
    if (!is_name(e.name)) {
        r.fail(n["name"], at + ".name", fmt::format("'{}' is not a name (a letter, then letters, digits, _ or -)", e.name));
    }
    const std::string key = "parts." + e.name;
    if (!n["type"]) r.fail(n, key + ".type", fmt::format("missing: one of {}", registry.type_list()));
    e.type = r.text(n["type"], key + ".type");
    const PartType* type = registry.find(e.type);
    if (type == nullptr) {
        r.fail(n["type"], key + ".type",
               fmt::format("unknown part type '{}' (known: {}; `ddmr-hil parts` lists them)", e.type, registry.type_list()));
    }
    std::vector<std::string> allowed = {"name", "type"};
    for (const PartKey& k : type->keys) allowed.push_back(k.name);
    r.only_keys(n, key, allowed);
    for (const PartKey& k : type->keys) {
        const YAML::Node v = n[k.name];
        if (!v) {
            if (k.required) r.fail(n, key + "." + k.name, fmt::format("missing: the {} {}", e.type, k.description));
            e.values[k.name] = PartEntry::Value{k.default_value, -1, 0};
            continue;
        }
        e.values[k.name] = read_value(r, v, key + "." + k.name, k, pin);
    }
    if (type->check) {
        if (const std::optional<PartKeyProblem> p = type->check(e, board)) {
            const YAML::Node at_key = n[p->key];
            r.fail(at_key ? at_key : n, key + "." + p->key, p->message);
        }
    }
    return e;
}

}  // namespace

std::vector<PartEntry> read_part_entries(const YamlReader& reader, const YAML::Node& list, const PinReader& pin,
                                         const PartRegistry& registry, const BoardDescription& board) {
    if (!list.IsSequence()) reader.fail(list, "parts", "expected a list of parts (- name: ..., type: ...)");
    std::vector<PartEntry> out;
    std::set<std::string> names;
    for (std::size_t i = 0; i < list.size(); ++i) {
        PartEntry e = read_entry(reader, list[i], i, pin, registry, board);
        if (!names.insert(e.name).second) {
            reader.fail(list[i]["name"], "parts." + e.name + ".name", fmt::format("a second part called '{}'", e.name));
        }
        out.push_back(std::move(e));
    }
    return out;
}

}  // namespace ddmr::hil
