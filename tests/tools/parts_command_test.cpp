// `ddmr-hil parts` (tools/parts_command.cpp) and the docs made from it: the
// listing shows every registered part type with its keys and output ports,
// an unknown type is one line and exit 2, and docs/boards.md's parts table and
// docs/schema/board.schema.json's parts items are exactly what `--markdown`
// and `--schema` print now (a part added without `make docs-parts` fails
// here). The schema is also run, as an editor would, on board files with
// parts.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

#include "hil/parts/part_registry.hpp"
#include "parts_command.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

const char* const kRegenerate =
    "\nThe docs are made from the part registry: run `make docs-parts` "
    "(tools/update_parts_docs.py build/ddmr-hil) and commit docs/boards.md and docs/schema/board.schema.json.";

ProcessResult parts(const std::string& args) { return run_command(sh_quote(cli_path().string()) + " parts" + args); }

/// The key or port line of the text listing ("        NAME  ..."), its runs
/// of spaces made one: "NAME input, required serial data in, ...", or "".
std::string listed(const std::string& out, const std::string& name) {
    const std::size_t at = out.find("\n        " + name + " ");
    if (at == std::string::npos) return "";
    const std::string line = out.substr(at + 9, out.find('\n', at + 1) - at - 9);
    std::string squeezed;
    for (const char c : line) {
        if (c != ' ' || squeezed.empty() || squeezed.back() != ' ') squeezed += c;
    }
    return squeezed;
}

bool lists_line(const std::string& out, const std::string& name) { return !listed(out, name).empty(); }

TEST(PartsCommand, ListsThe74hc595WithItsKeysAndPorts) {
    const ProcessResult r = parts("");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_NE(r.out.find("\n  74hc595: 8-bit shift register"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("datasheet: Nexperia 74HC595"), std::string::npos) << r.out;
    for (const char* key : {"DS", "SHCP", "STCP"}) {
        EXPECT_EQ(listed(r.out, key).rfind(std::string(key) + " input, required ", 0), 0U) << key << "\n" << r.out;
    }
    EXPECT_EQ(listed(r.out, "DS").rfind("DS input, required serial data in, sampled at SHCP's rising edge", 0), 0U)
        << r.out;
    EXPECT_EQ(listed(r.out, "OE").rfind("OE input, default low output enable, active low", 0), 0U) << r.out;
    EXPECT_EQ(listed(r.out, "MR").rfind("MR input, default high master reset, active low", 0), 0U) << r.out;
    for (int i = 0; i < 8; ++i) EXPECT_TRUE(lists_line(r.out, "Q" + std::to_string(i))) << i << "\n" << r.out;
    EXPECT_TRUE(lists_line(r.out, "Q7S")) << r.out;
    // Every registered type, in the registry's order.
    std::size_t at = 0;
    for (const hil::PartType* t : hil::PartRegistry::global().types()) {
        const std::size_t p = r.out.find("\n  " + t->type + ": " + t->summary + "\n");
        ASSERT_NE(p, std::string::npos) << t->type;
        EXPECT_GE(p, at) << t->type;
        at = p;
    }
}

TEST(PartsCommand, ShowsOneType) {
    const ProcessResult r = parts(" 74hc595");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("\n  74hc595: "), std::string::npos) << r.out;
    EXPECT_TRUE(lists_line(r.out, "SHCP")) << r.out;
    EXPECT_TRUE(lists_line(r.out, "Q7S")) << r.out;
    // Its block is the one the full listing has.
    const std::string block = r.out.substr(r.out.find("\n  74hc595: "));
    EXPECT_NE(parts("").out.find(block), std::string::npos) << block;
    const ProcessResult md = parts(" 74hc595 --markdown");
    ASSERT_EQ(md.exit_code, 0) << md.err;
    EXPECT_NE(md.out.find("| `DS` | input | required | a pin, `NAME.PORT`, `high`, `low` | serial data in"),
              std::string::npos)
        << md.out;
    EXPECT_NE(md.out.find("| `OE` | input | `low` |"), std::string::npos) << md.out;
    EXPECT_NE(md.out.find("| `Q7S` | serial out"), std::string::npos) << md.out;
}

TEST(PartsCommand, AWheelPartNamesThePlantSectionOfItsParameters) {
    // The chip's section of the plant file (plant/params/default.yaml): the
    // L293D has its own, the L298N module is the L298 (`driver:`).
    EXPECT_NE(parts(" l293d").out.find("\n      plant parameters: the plant file's `l293d:` section (drop_V, "),
              std::string::npos);
    EXPECT_NE(parts(" l298n").out.find("plant parameters: the plant file's `driver:` section"), std::string::npos);
    EXPECT_NE(parts(" quadrature --markdown").out.find("Plant parameters: the plant file's `encoder1:` (right wheel)"),
              std::string::npos);
    EXPECT_EQ(parts(" 74hc595").out.find("plant parameters"), std::string::npos);  // a logic chip has none
}

TEST(PartsCommand, AnUnknownTypeIsOneLineNamingTheKnownOnes) {
    const ProcessResult r = parts(" nosuch");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "one line: " << r.err;
    EXPECT_NE(r.err.find("unknown part type 'nosuch'"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(the types: " + hil::PartRegistry::global().type_list() + ")"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("74hc595"), std::string::npos) << r.err;
    // --markdown and --schema are two different outputs: not both.
    EXPECT_EQ(parts(" --markdown --schema").exit_code, 2);
}

// Every kind of key, on a made-up type (the built-in 74hc595 has inputs only):
// an output pin, a numeric option and an option of words, in all three forms.
TEST(PartsCommand, ShowsOutputPinsAndOptions) {
    hil::PartType t;
    t.type = "probe";
    t.summary = "a test part";
    t.datasheet = "none";
    t.keys = {
        hil::PartKey::input("IN", "what it reads"),
        hil::PartKey::output("OUT", "what it drives"),
        hil::PartKey::number("GAIN", "how much", 2.5, 0.0, 10.0),
        hil::PartKey::choice("MODE", "how", {"fast", "slow"}),
    };
    t.ports = {{"Y", "a port"}};
    const std::vector<const hil::PartType*> types{&t};

    const std::string text = tools::parts_text(types);
    EXPECT_EQ(listed(text, "OUT"), "OUT output, required what it drives") << text;
    EXPECT_EQ(listed(text, "GAIN"), "GAIN option, default 2.5, 0..10 how much") << text;
    EXPECT_EQ(listed(text, "MODE"), "MODE option, default fast, one of fast, slow how") << text;
    EXPECT_EQ(listed(text, "Y"), "Y a port") << text;

    const std::string md = tools::parts_markdown(types);
    EXPECT_NE(md.find("| `OUT` | output | required | a pin | what it drives |"), std::string::npos) << md;
    EXPECT_NE(md.find("| `GAIN` | option | `2.5` | a number in [0, 10] | how much |"), std::string::npos) << md;
    EXPECT_NE(md.find("| `MODE` | option | `fast` | `fast`, `slow` | how |"), std::string::npos) << md;

    const nlohmann::json schema = tools::parts_schema(types);
    const nlohmann::json& keys = schema["allOf"][0]["then"]["properties"];
    EXPECT_EQ(keys["OUT"]["$ref"], "#/$defs/pin");
    EXPECT_EQ(keys["GAIN"]["type"], "number");
    EXPECT_EQ(keys["GAIN"]["minimum"], 0);
    EXPECT_EQ(keys["GAIN"]["maximum"], 10);
    EXPECT_EQ(keys["GAIN"]["default"], 2.5);
    EXPECT_EQ(keys["MODE"]["enum"], nlohmann::json({"fast", "slow"}));
    EXPECT_EQ(keys["MODE"]["default"], "fast");
    EXPECT_EQ(schema["allOf"][0]["then"]["required"], nlohmann::json({"IN", "OUT"}));
    EXPECT_EQ(schema["allOf"][0]["then"]["additionalProperties"], false);
}

/// What lies between docs/boards.md's parts-table markers.
std::string boards_md_table() {
    const std::string md = read_text(source_dir() / "docs/boards.md");
    const std::string begin = "<!-- parts-table:begin -->\n", end = "<!-- parts-table:end -->";
    const std::size_t b = md.find(begin);
    const std::size_t e = md.find(end);
    if (b == std::string::npos || e == std::string::npos || e < b) return "(no parts-table markers)";
    return md.substr(b + begin.size(), e - b - begin.size());
}

TEST(PartsDocs, BoardsMdHasTheTableTheRegistryMakes) {
    const ProcessResult r = parts(" --markdown");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(boards_md_table(), "\n" + r.out + "\n")
        << "docs/boards.md's parts table is not what `ddmr-hil parts --markdown` prints." << kRegenerate;
}

TEST(PartsDocs, BoardSchemaHasThePartsItemsTheRegistryMakes) {
    const ProcessResult r = parts(" --schema");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto made = nlohmann::json::parse(r.out);
    const auto schema = nlohmann::json::parse(read_text(source_dir() / "docs/schema/board.schema.json"));
    const auto items = schema.value("/properties/parts/items"_json_pointer, nlohmann::json());
    EXPECT_EQ(items, made) << "docs/schema/board.schema.json's properties.parts.items is not what `ddmr-hil parts "
                              "--schema` prints."
                           << kRegenerate;
    // What the items refer to is the board schema's own.
    EXPECT_TRUE(schema.contains("/$defs/pin"_json_pointer));
    EXPECT_TRUE(schema.contains("/$defs/partInput"_json_pointer));
}

// The board schema with parts, run as an editor runs it: a shield's
// 74HC595 feeding two L293D wheels passes; an unknown part type, an unknown
// or missing key, an option out of its words and an input that is none of
// pin / NAME.PORT / high / low do not.
TEST(PartsDocs, TheBoardSchemaChecksParts) {
    const auto validate = [](const fs::path& file) {
        return run_command("/usr/bin/python3 " +
                           sh_quote((source_dir() / "tests/tools/validate_yaml_schema.py").string()) + " " +
                           sh_quote((source_dir() / "docs/schema/board.schema.json").string()) + " " +
                           sh_quote(file.string()));
    };
    const std::string wheels =
        "wheels:\n"
        "  right:\n"
        "    motor: {driver: l293d, EN: 11, IN1: shield.Q2, IN2: shield.Q3}\n"
        "  left:\n"
        "    motor: {driver: l293d, EN: high, IN1: shield.Q1, IN2: shield.Q4}\n";
    TempDir dir;
    std::ofstream(dir / "good.yaml") << "board: uno\nparts:\n  - {name: shield, type: 74hc595, DS: 8, SHCP: D4, "
                                        "STCP: 12, OE: low}\n"
                                     << wheels;
    ProcessResult r = validate(dir / "good.yaml");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    r = validate(source_dir() / "firmware/examples/afmotor_shield_v1/board.yaml");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;

    const char* const bad[] = {
        "  - {name: shield, type: 74hc596, DS: 8, SHCP: 4, STCP: 12}\n",          // unknown type
        "  - {name: shield, type: 74hc595, DS: 8, SHCP: 4, STCP: 12, Q0: 9}\n",   // unknown key (a port)
        "  - {name: shield, type: 74hc595, DS: 8, SHCP: 4}\n",                    // STCP missing
        "  - {type: 74hc595, DS: 8, SHCP: 4, STCP: 12}\n",                        // no name
        "  - {name: shield, type: 74hc595, DS: 8, SHCP: 4, STCP: 12, OE: maybe}\n",  // not an input
        "  - {name: shield, type: 74hc595, DS: 8, SHCP: 1, STCP: 12}\n",          // pin 1 is Serial's
    };
    int k = 0;
    for (const char* entry : bad) {
        const fs::path f = dir / ("bad" + std::to_string(k++) + ".yaml");
        std::ofstream(f) << "board: uno\nparts:\n" << entry << wheels;
        r = validate(f);
        EXPECT_EQ(r.exit_code, 1) << entry << r.out << r.err;
        EXPECT_NE(r.out.find(f.string() + ": parts/0"), std::string::npos) << entry << r.out;
    }
    // A sensor on a servo's horn takes its place from the servo: its own x_mm is refused.
    const std::string pan = "board: uno\nparts:\n  - {name: pan, type: servo, SIGNAL: 9, x_mm: 60}\n";
    std::ofstream(dir / "mounted.yaml") << pan << "  - {name: s, type: ultrasonic, TRIG: 7, ECHO: 8, mount: pan}\n"
                                        << wheels;
    r = validate(dir / "mounted.yaml");
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    std::ofstream(dir / "placed_twice.yaml")
        << pan << "  - {name: s, type: ultrasonic, TRIG: 7, ECHO: 8, mount: pan, x_mm: 50}\n" << wheels;
    r = validate(dir / "placed_twice.yaml");
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_NE(r.out.find("parts/1"), std::string::npos) << r.out;
}

}  // namespace
}  // namespace ddmr::test
