// docs/schema/scenario.schema.json (issue 19, item 9): the JSON Schema
// editors use to complete and check scenario files. It accepts every scenario
// file the project ships, refuses the mistakes the parser refuses, and knows
// exactly the parser's step kinds (the step catalogue). Validated with
// Debian's python3-jsonschema, as an editor's YAML extension would.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <set>
#include <string>

#include "scenario/step_catalog.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

const fs::path kSchema = source_dir() / "docs/schema/scenario.schema.json";

ProcessResult validate(const std::string& files) {
    return run_command("/usr/bin/python3 " + sh_quote((source_dir() / "tests/tools/validate_yaml_schema.py").string()) +
                       " " + sh_quote(kSchema.string()) + " " + files);
}

TEST(ScenarioSchema, AcceptsEveryShippedScenario) {
    std::string files;
    int n = 0;
    for (const fs::path& dir : {source_dir() / "tests/scenarios", source_dir() / "firmware/examples"}) {
        for (const auto& e : fs::recursive_directory_iterator(dir)) {
            if (e.path().extension() != ".yaml") continue;
            if (read_text(e.path()).find("\nsteps:") == std::string::npos) continue;  // boards, contracts
            files += " " + sh_quote(e.path().string());
            ++n;
        }
    }
    EXPECT_GE(n, 14);  // 7 in tests/scenarios, 7 examples
    const ProcessResult r = validate(files);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
}

// The board and plant schemas, the same way: every shipped file passes, a
// misspelled key and a value out of its range do not.
TEST(BoardAndPlantSchemas, AcceptShippedFilesAndRefuseMistakes) {
    const auto run = [](const char* schema, const std::string& files) {
        return run_command("/usr/bin/python3 " +
                           sh_quote((source_dir() / "tests/tools/validate_yaml_schema.py").string()) + " " +
                           sh_quote((source_dir() / "docs/schema" / schema).string()) + " " + files);
    };
    std::string boards = sh_quote((source_dir() / "firmware/ddmr_tracking/board.yaml").string());
    std::string plants = sh_quote((source_dir() / "plant/params/default.yaml").string()) + " " +
                         sh_quote((source_dir() / "tests/tools/calibrate/data/perturbed_robot.yaml").string());
    for (const auto& e : fs::directory_iterator(source_dir() / "firmware/examples")) {
        if (fs::exists(e.path() / "board.yaml")) boards += " " + sh_quote((e.path() / "board.yaml").string());
        if (fs::exists(e.path() / "plant.yaml")) plants += " " + sh_quote((e.path() / "plant.yaml").string());
    }
    auto r = run("board.schema.json", boards);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    r = run("plant.schema.json", plants);
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;

    TempDir dir;
    std::ofstream(dir / "plant.yaml") << "motor1:\n  resistnce_ohm: 5\nencoder1:\n  initial_phase: 1.0\n";
    r = run("plant.schema.json", sh_quote((dir / "plant.yaml").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    std::ofstream(dir / "board.yaml") << read_text(source_dir() / "firmware/ddmr_tracking/board.yaml") << "pullup: true\n";
    r = run("board.schema.json", sh_quote((dir / "board.yaml").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
}

TEST(ScenarioSchema, RefusesWhatTheParserRefuses) {
    TempDir dir;
    const std::pair<const char*, const char*> cases[] = {
        {"timout: 1s\nsteps:\n  - delay: 1ms\n", "(top)"},                              // misspelled key
        {"timeout: 1s\nsteps:\n  - dance: 1ms\n", "steps/0"},                           // unknown step
        {"timeout: 1s\nsteps:\n  - wait-serial: {text: END, timout: 1s}\n", "steps/0"},  // misspelled step key
        {"timeout: 1s\nsteps:\n  - delay: 100\n", "steps/0"},                           // a duration without a unit
        {"timeout: 1s\nsteps:\n  - expect: {signal: x_m, op: \"=>\", value: 1}\n", "steps/0"},
        {"timeout: 1s\nfirmware: {sketch: a/a.ino}\nlibraries: libs\nsteps:\n  - delay: 1ms\n", "libraries"},  // not a list
        {"timeout: 1s\nfirmware: {platformio: p, elf: x.elf}\nsteps:\n  - delay: 1ms\n", "firmware"},  // two firmwares
        {"timeout: 1s\nfirmware: {elf: x.elf, env: uno}\nsteps:\n  - delay: 1ms\n", "firmware"},  // env without platformio
    };
    int k = 0;
    for (const auto& [text, where] : cases) {
        const fs::path f = dir / ("bad" + std::to_string(k++) + ".yaml");
        std::ofstream(f) << text;
        const ProcessResult r = validate(sh_quote(f.string()));
        EXPECT_EQ(r.exit_code, 1) << text << r.out << r.err;
        EXPECT_NE(r.out.find(f.string() + ": " + where), std::string::npos) << text << r.out;
    }
}

TEST(ScenarioSchema, KnowsExactlyTheParsersSteps) {
    const auto schema = nlohmann::json::parse(read_text(kSchema));
    std::set<std::string> in_schema;
    for (const auto& alt : schema["$defs"]["step"]["anyOf"]) {
        if (alt.contains("properties")) {
            for (const auto& [kind, _] : alt["properties"].items()) in_schema.insert(kind);
        }
    }
    std::set<std::string> in_catalogue;
    for (const auto& s : tools::scenario::step_catalog()) in_catalogue.insert(std::string(s.kind));
    EXPECT_EQ(in_schema, in_catalogue);
}

}  // namespace
}  // namespace ddmr::test
