// `ddmr-hil parts [TYPE] [--markdown | --schema]` (parts_command.hpp): every
// text here is made from the PartRegistry, so a new part type is listed,
// documented and in the schema without touching this file.
#include "parts_command.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "exit_codes.hpp"
#include "hil/parts/part_registry.hpp"

namespace ddmr::tools {
namespace {

using hil::PartKey;
using hil::PartKeyKind;
using hil::PartPort;
using hil::PartType;

const char* kind_word(PartKeyKind kind) {
    switch (kind) {
        case PartKeyKind::input: return "input";
        case PartKeyKind::output_pin: return "output";
        case PartKeyKind::option: return "option";
        case PartKeyKind::carrier: return "carrier";
    }
    return "?";
}

/// "required", "default low", or a carrier's "default: none".
std::string required_or_default(const PartKey& k) {
    if (k.required) return "required";
    return k.kind == PartKeyKind::carrier ? std::string("default: none") : "default " + k.default_value;
}

/// An option's allowed values ("0..10", "one of fast, slow"); empty for pins and inputs.
std::string option_values(const PartKey& k) {
    if (k.kind != PartKeyKind::option) return {};
    if (!k.choices.empty()) {
        std::string words;
        for (const std::string& c : k.choices) words += (words.empty() ? "" : ", ") + c;
        return "one of " + words;
    }
    return fmt::format("{}..{}", k.lo, k.hi);
}

std::string key_line_middle(const PartKey& k) {
    std::string s = fmt::format("{}, {}", kind_word(k.kind), required_or_default(k));
    const std::string values = option_values(k);
    if (!values.empty()) s += ", " + values;
    return s;
}

void append_type_text(std::string& t, const PartType& type) {
    t += fmt::format("\n  {}: {}\n      datasheet: {}\n", type.type, type.summary, type.datasheet);
    std::size_t name_w = 0, middle_w = 0;
    for (const PartKey& k : type.keys) {
        name_w = std::max(name_w, k.name.size());
        middle_w = std::max(middle_w, key_line_middle(k).size());
    }
    for (const PartPort& p : type.ports) name_w = std::max(name_w, p.name.size());
    if (!type.keys.empty()) t += "      keys:\n";
    for (const PartKey& k : type.keys) {
        t += fmt::format("        {:<{}}  {:<{}}  {}\n", k.name, name_w, key_line_middle(k), middle_w, k.description);
    }
    if (!type.ports.empty()) t += "      outputs (other parts read them as NAME.PORT):\n";
    for (const PartPort& p : type.ports) t += fmt::format("        {:<{}}  {}\n", p.name, name_w, p.description);
    if (!type.plant_parameters.empty()) t += fmt::format("      plant parameters: {}\n", type.plant_parameters);
    if (!type.readings.empty()) t += "      readings a test may hold (Python: sensor(NAME).set):\n";
    for (const hil::SettableReading& r : type.readings) {
        t += fmt::format("        {}  {}..{}  {}\n", r.name, r.lo, r.hi, r.description);
    }
}

/// A table cell: '|' escaped, no line breaks.
std::string cell(const std::string& text) {
    std::string out;
    for (const char c : text) {
        if (c == '|') {
            out += "\\|";
        } else {
            out += (c == '\n' ? ' ' : c);
        }
    }
    return out;
}

std::string code_list(const std::vector<std::string>& words) {
    std::string out;
    for (const std::string& w : words) out += (out.empty() ? "`" : ", `") + w + "`";
    return out;
}

std::string markdown_values(const PartKey& k) {
    switch (k.kind) {
        case PartKeyKind::input: return "a pin, `NAME.PORT`, `high`, `low`";
        case PartKeyKind::output_pin: return "a pin";
        case PartKeyKind::carrier: return "a part's name";
        case PartKeyKind::option: break;
    }
    if (!k.choices.empty()) return code_list(k.choices);
    return fmt::format("a number in [{}, {}]", k.lo, k.hi);
}

void append_type_markdown(std::string& t, const PartType& type) {
    t += fmt::format("\n### `{}`: {}\n\nSource: {}.\n\n", type.type, cell(type.summary), cell(type.datasheet));
    if (!type.plant_parameters.empty()) t += fmt::format("Plant parameters: {}.\n\n", type.plant_parameters);
    if (!type.keys.empty()) {
        t += "| key | kind | required / default | values | meaning |\n| --- | --- | --- | --- | --- |\n";
        for (const PartKey& k : type.keys) {
            const std::string req = k.required                          ? std::string("required")
                                    : k.kind == PartKeyKind::carrier ? std::string("none")
                                                                     : "`" + k.default_value + "`";
            t += fmt::format("| `{}` | {} | {} | {} | {} |\n", k.name, kind_word(k.kind), req, markdown_values(k),
                             cell(k.description));
        }
        t += "\n";
    }
    if (!type.ports.empty()) {
        t += "| output port | meaning |\n| --- | --- |\n";
        for (const PartPort& p : type.ports) t += fmt::format("| `{}` | {} |\n", p.name, cell(p.description));
    }
    if (!type.readings.empty()) {
        t += "\n| reading a test may hold (`sensor(NAME).set`, docs/python.md) | values | meaning |\n| --- | --- | --- |\n";
        for (const hil::SettableReading& r : type.readings) {
            t += fmt::format("| `{}` | [{}, {}] | {} |\n", r.name, r.lo, r.hi, cell(r.description));
        }
    }
}

/// A number as JSON: an integer when it is one (10, not 10.0).
nlohmann::ordered_json json_number(double v) {
    if (std::isfinite(v) && std::floor(v) == v && std::fabs(v) < 9.0e15) return static_cast<std::int64_t>(v);
    return v;
}

nlohmann::ordered_json key_schema(const PartKey& k) {
    nlohmann::ordered_json s;
    switch (k.kind) {
        case PartKeyKind::input: s["$ref"] = "#/$defs/partInput"; break;
        case PartKeyKind::output_pin: s["$ref"] = "#/$defs/pin"; break;
        case PartKeyKind::carrier: s["type"] = "string"; break;
        case PartKeyKind::option:
            if (!k.choices.empty()) {
                s["enum"] = k.choices;
            } else {
                s["type"] = "number";
                s["minimum"] = json_number(k.lo);
                s["maximum"] = json_number(k.hi);
            }
            break;
    }
    if (!k.required && k.kind != PartKeyKind::carrier) {
        if (k.kind == PartKeyKind::option && k.choices.empty()) {
            s["default"] = json_number(std::stod(k.default_value));
        } else {
            s["default"] = k.default_value;
        }
    }
    const char* kind = k.kind == PartKeyKind::input        ? "Input"
                       : k.kind == PartKeyKind::output_pin ? "Output pin"
                       : k.kind == PartKeyKind::carrier    ? "A part's name"
                                                           : "Option";
    s["description"] = fmt::format("{}. {}, {}.", k.description, kind, required_or_default(k));
    return s;
}

/// `if type is T then only T's keys, its required ones present`.
nlohmann::ordered_json type_clause(const PartType& type) {
    nlohmann::ordered_json then;
    then["description"] = fmt::format("{}: {}. Source: {}.", type.type, type.summary, type.datasheet);
    std::vector<std::string> required;
    for (const PartKey& k : type.keys) {
        if (k.required) required.push_back(k.name);
    }
    if (!required.empty()) then["required"] = required;
    nlohmann::ordered_json props;
    props["name"] = true;
    props["type"] = true;
    for (const PartKey& k : type.keys) props[k.name] = key_schema(k);
    then["properties"] = props;
    then["additionalProperties"] = false;
    for (const PartKey& k : type.keys) {
        // A part on a carrier takes its place from it (hil/parts/sensor_mount.cpp, check_mount).
        if (k.kind != PartKeyKind::carrier) continue;
        nlohmann::ordered_json placed = nlohmann::ordered_json::array();
        for (const char* own : {"x_mm", "y_mm", "heading_deg"}) placed.push_back({{"required", {own}}});
        then["dependentSchemas"][k.name] = {{"not", {{"anyOf", placed}}}};
    }
    nlohmann::ordered_json clause;
    clause["if"] = {{"properties", {{"type", {{"const", type.type}}}}}, {"required", {"type"}}};
    clause["then"] = then;
    return clause;
}

struct PartsCli {
    std::string type;
    bool markdown = false;
    bool schema = false;
};

int run_parts(const PartsCli& cli) {
    const hil::PartRegistry& registry = hil::PartRegistry::global();
    std::vector<const PartType*> types = registry.types();
    if (!cli.type.empty()) {
        const PartType* t = registry.find(cli.type);
        if (t == nullptr) {
            throw std::invalid_argument(
                fmt::format("unknown part type '{}' (the types: {})", cli.type, registry.type_list()));
        }
        types = {t};
    }
    std::string out;
    if (cli.markdown) {
        out = parts_markdown(types);
    } else if (cli.schema) {
        out = parts_schema(types).dump(2) + "\n";
    } else {
        out = parts_text(types);
    }
    std::fputs(out.c_str(), stdout);
    return kExitOk;
}

}  // namespace

std::string parts_text(const std::vector<const PartType*>& types) {
    std::string t =
        "Part types for the board file's parts: list (docs/boards.md, \"Parts\"; `ddmr-hil parts TYPE` shows one).\n"
        "An input is a pin, NAME.PORT (another part's output), high or low; an output is a pin the part drives;\n"
        "an option is a number or one of its words.\n";
    for (const PartType* type : types) append_type_text(t, *type);
    return t;
}

std::string parts_markdown(const std::vector<const PartType*>& types) {
    std::string t = "| type | part | keys | output ports |\n| --- | --- | --- | --- |\n";
    for (const PartType* type : types) {
        std::vector<std::string> keys, ports;
        for (const PartKey& k : type->keys) keys.push_back(k.name);
        for (const PartPort& p : type->ports) ports.push_back(p.name);
        t += fmt::format("| `{}` | {} | {} | {} |\n", type->type, cell(type->summary), code_list(keys),
                         code_list(ports));
    }
    for (const PartType* type : types) append_type_markdown(t, *type);
    return t;
}

nlohmann::ordered_json parts_schema(const std::vector<const PartType*>& types) {
    std::vector<std::string> words;
    std::string described;
    for (const PartType* type : types) {
        words.push_back(type->type);
        described += fmt::format("{}{}: {}", described.empty() ? "" : "; ", type->type, type->summary);
    }
    nlohmann::ordered_json s;
    s["description"] =
        "One part (docs/boards.md, \"Parts\"): its name, its type and that type's keys. Made from the part registry "
        "by `ddmr-hil parts --schema` (`make docs-parts` writes it here).";
    s["type"] = "object";
    s["properties"]["name"] = {
        {"type", "string"},
        {"pattern", "^[^.\\s]+$"},
        {"description",
         "The part's name, unique on the board (no dot): other parts and wheels read its outputs as NAME.PORT "
         "(shield.Q2)."}};
    s["properties"]["type"] = {{"enum", words},
                               {"description", "The part type (`ddmr-hil parts` lists them). " + described + "."}};
    s["required"] = {"name", "type"};
    nlohmann::ordered_json clauses = nlohmann::ordered_json::array();
    for (const PartType* type : types) clauses.push_back(type_clause(*type));
    s["allOf"] = clauses;
    return s;
}

Subcommand register_parts_command(CLI::App& app) {
    auto cli = std::make_shared<PartsCli>();
    CLI::App* sub = app.add_subcommand(
        "parts",
        "List the part types a board file's parts: list can name (docs/boards.md, \"Parts\"): each one's keys "
        "(inputs, output pins, options; required or their defaults) and output ports. Exit 0, 2 an unknown type.");
    sub->add_option("type", cli->type, "Show only this part type");
    CLI::Option* markdown =
        sub->add_flag("--markdown", cli->markdown, "Print the parts table of docs/boards.md (Markdown) instead");
    CLI::Option* schema = sub->add_flag(
        "--schema", cli->schema,
        "Print the JSON Schema of one parts: item (docs/schema/board.schema.json's properties.parts.items) instead");
    markdown->excludes(schema);
    return {sub, [cli] { return run_parts(*cli); }};
}

}  // namespace ddmr::tools
