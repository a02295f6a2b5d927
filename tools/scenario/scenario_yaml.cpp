// Loads a scenario file (scenario_yaml.hpp): its settings in the order each
// gives meaning to the next (board, firmware, run settings, plant), then its
// steps (step_parsers.hpp, one file per family of steps).
#include "scenario/scenario_yaml.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <optional>
#include <regex>
#include <sstream>

#include "common/arduino_libraries.hpp"
#include "common/platformio_project.hpp"
#include "common/plant_yaml.hpp"
#include "hil/board.hpp"
#include "hil/world_file.hpp"
#include "plant/params_yaml.hpp"
#include "scenario/step_parsers.hpp"
#include "scenario/yaml_ctx.hpp"

namespace ddmr::tools::scenario {
namespace fs = std::filesystem;

Cycles parse_duration(std::string_view text, uint32_t clock_hz) {
    const std::string s(text);
    static const std::regex re(R"(^\s*([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)\s*(s|ms|us|cycles)\s*$)");
    std::smatch m;
    if (!std::regex_match(s, m, re)) {
        throw std::invalid_argument(fmt::format(
            "duration '{}': expected a non-negative number with a unit (s, ms, us or cycles), e.g. 500ms", s));
    }
    double value = 0.0;
    try {
        value = std::stod(m[1].str());
    } catch (const std::out_of_range&) {
        throw std::invalid_argument(fmt::format("duration '{}': too large", s));
    }
    const std::string unit = m[2].str();
    const double scale = unit == "s" ? clock_hz : unit == "ms" ? clock_hz / 1e3 : unit == "us" ? clock_hz / 1e6 : 1.0;
    const double cycles = std::round(value * scale);
    if (!std::isfinite(cycles) || cycles > 1e15) {
        throw std::invalid_argument(fmt::format("duration '{}': too large", s));
    }
    return static_cast<Cycles>(cycles);
}

namespace {

using yaml::Ctx;
using yaml::existing_file;

std::string step_text(const YAML::Node& step) {
    YAML::Emitter e;
    e.SetMapFormat(YAML::Flow);
    e.SetSeqFormat(YAML::Flow);
    e << step;
    return e.c_str();
}

/// The text of a scenario as YAML: a mapping (its keys are checked later).
YAML::Node load_root(std::string_view yaml_text, const fs::path& file) {
    YAML::Node root;
    try {
        root = YAML::Load(std::string(yaml_text));
    } catch (const YAML::Exception& e) {
        throw ScenarioError(fmt::format("{}:{}: malformed YAML: {}", file.string(), e.mark.line + 1, e.msg));
    }
    if (!root.IsMap()) throw ScenarioError(fmt::format("{}:1: a scenario is a mapping with a 'steps' list", file.string()));
    return root;
}

/// world: a world file (docs/world.md).
void read_world_file(const YAML::Node& root, const fs::path& file, Scenario& s) {
    if (!root["world"]) return;
    s.world_file = existing_file(Ctx(file, root["world"], "world", hil::board_description(s.board.model)));
    try {
        s.world = hil::load_world_file(*s.world_file);  // its messages name its file, line and key
    } catch (const std::runtime_error& e) {
        throw ScenarioError(e.what());
    }
}

/// board: a board file. Read first: its clock and pins give meaning to the rest.
void read_board_file(const YAML::Node& root, const fs::path& file, Scenario& s) {
    if (root["board"]) {
        s.board_file = existing_file(Ctx(file, root["board"], "board", hil::board_description(s.board.model)));
        try {
            s.board = hil::load_board_file(*s.board_file);  // its messages name its file, line and key
        } catch (const std::runtime_error& e) {
            throw ScenarioError(e.what());
        }
    }
}

/// firmware: {platformio, env}: a PlatformIO project names its board, so it
/// is read before anything the board gives meaning to.
std::optional<PlatformioProject> read_platformio(const YAML::Node& root, const fs::path& file,
                                                 const LoadOptions& options, Scenario& s) {
    std::optional<PlatformioProject> pio;
    if (!options.firmware_override && root["firmware"] && root["firmware"].IsMap() && root["firmware"]["platformio"]) {
        const Ctx c(file, root["firmware"], "firmware", hil::board_description(s.board.model), &s.board);
        c.keys({"platformio", "env"}, {"platformio"});
        const Ctx d = c.child("platformio");
        const fs::path p(d.str());
        if (p.is_absolute()) d.fail(fmt::format("'{}' is absolute: a scenario's paths are relative to its file", p.string()));
        const std::string env = c.has("env") ? c.child("env").str() : std::string();
        try {
            pio = load_platformio_project((fs::absolute(file).parent_path() / p).lexically_normal(), env);
        } catch (const std::invalid_argument& e) {
            d.fail(e.what());
        }
        if (s.board_file && s.board.model != pio->board) {
            d.fail(fmt::format("[env:{}] is for board {} ({}), the board file {} for {}", pio->env, pio->board_id,
                               hil::board_description(pio->board).key, s.board_file->string(),
                               hil::board_description(s.board.model).key));
        }
        s.board.model = pio->board;  // without a board file: the thesis robot's wiring on that board
        s.firmware = pio->elf;
        s.firmware_source = platformio_json(*pio);
    }
    return pio;
}

/// firmware: the command line's, else the file's (an ELF, a sketch to build,
/// or a PlatformIO project, read by read_platformio()), else the reference.
void read_firmware(const Ctx& top, const YAML::Node& root, const LoadOptions& options, bool from_platformio,
                   Scenario& s) {
    if (options.firmware_override) {
        s.firmware = *options.firmware_override;
    } else if (from_platformio) {
        // read above
    } else if (root["firmware"] && root["firmware"].IsMap()) {
        const Ctx c = top.at(root["firmware"], "firmware");
        c.keys({"elf", "sketch", "platformio", "env"});
        if (c.has("elf") == c.has("sketch")) {
            c.fail("give one of elf (a built ELF), sketch (a .ino to build) or platformio (a project folder)");
        }
        if (c.has("env")) c.child("env").fail("only with platformio: DIR (the environment of a PlatformIO project)");
        if (c.has("elf")) {
            s.firmware = existing_file(c.child("elf"));
        } else {
            const fs::path ino = existing_file(c.child("sketch"));
            if (ino.extension() != ".ino") c.child("sketch").fail(fmt::format("'{}' is not a .ino sketch", ino.string()));
            if (ino.parent_path().filename() != ino.stem()) {
                c.child("sketch").fail(fmt::format("Arduino needs the sketch in a folder of its name ({0}/{0}.ino)",
                                                   ino.stem().string()));
            }
            s.sketch = ino;
        }
    } else if (root["firmware"] && top.at(root["firmware"], "firmware").str() != "reference") {
        s.firmware = existing_file(top.at(root["firmware"], "firmware"));
    } else {
        s.firmware = options.reference_firmware;
    }
}

/// libraries: library folders for the sketch, relative to the scenario file
/// (they may be outside its folder: a sketchbook's libraries/ beside it).
void read_libraries(const Ctx& top, const YAML::Node& root, const LoadOptions& options, Scenario& s) {
    if (root["libraries"]) {
        const Ctx c = top.at(root["libraries"], "libraries");
        if (!s.sketch && !options.firmware_override) c.fail("only a scenario that builds a sketch (firmware: {sketch: x/x.ino}) takes libraries");
        if (!c.node().IsSequence()) c.fail("expected a list of folders, like [../libraries]");
        const fs::path folder = fs::absolute(top.file()).parent_path();
        for (std::size_t i = 0; i < c.node().size(); ++i) {
            const Ctx d = top.at(c.node()[i], fmt::format("libraries[{}]", i));
            const fs::path p(d.str());
            if (p.is_absolute()) {
                d.fail(fmt::format("'{}' is absolute: a scenario's library folders are relative to its file "
                                   "(give a machine's own folders with --libraries DIR)", p.string()));
            }
            const fs::path full = (folder / p).lexically_normal();
            if (!fs::is_directory(full)) d.fail(fmt::format("'{}' is not a folder ({})", p.string(), full.string()));
            if (const auto why = library_itself(full)) {
                d.fail(fmt::format("'{}' is a library itself ({}), not a folder of libraries: name the folder that "
                                   "holds it",
                                   p.string(), *why));
            }
            s.libraries.push_back(full);
        }
    }
}

/// seed, timeout, pwm, eeprom-timing, fast-forward: how the run goes.
void read_run_settings(const Ctx& top, const YAML::Node& root, Scenario& s) {
    if (root["seed"]) s.seed = top.at(root["seed"], "seed").count();
    if (root["fast-forward"]) s.fast_forward = top.at(root["fast-forward"], "fast-forward").boolean();
    s.timeout = top.at(root["timeout"], "timeout").duration();
    if (s.timeout == 0) top.at(root["timeout"], "timeout").fail("must be longer than 0");
    if (root["pwm"]) {
        const Ctx c = top.at(root["pwm"], "pwm");
        const std::string v = c.str();
        if (v == "switched") s.pwm = plant::DriveMode::switched;
        else if (v == "averaged") s.pwm = plant::DriveMode::averaged;
        else c.fail(fmt::format("'{}' is not switched or averaged", v));
    }
    if (root["eeprom-timing"]) {
        const Ctx c = top.at(root["eeprom-timing"], "eeprom-timing");
        const std::string v = c.str();
        if (v == "datasheet") s.eeprom_timing = hil::EepromTimingMode::kDatasheet;
        else if (v == "instant") s.eeprom_timing = hil::EepromTimingMode::kInstant;
        else c.fail(fmt::format("'{}' is not datasheet or instant", v));
    }
}

/// serial: {baud, port}: the host's serial adapter.
void read_serial(const Ctx& top, const YAML::Node& root, const hil::BoardDescription& board, Scenario& s) {
    if (root["serial"]) {
        const Ctx c = top.at(root["serial"], "serial");
        c.keys({"baud", "port"});
        if (c.has("baud")) s.baud = static_cast<uint32_t>(c.child("baud").integer_in(300, 2000000));
        if (c.has("port")) {
            const Ctx p = c.child("port");
            const std::string name = p.str();
            const std::optional<int> usart = hil::parse_serial_port(board, name);
            if (!usart) {
                p.fail(fmt::format("'{}' is not a serial port of the {} ({}): {}", name, board.label, board.mcu->label,
                                   hil::serial_port_list(board)));
            }
            s.serial_usart = *usart;
            hil::check_host_serial_pins(s.board, board.mcu->usarts[static_cast<std::size_t>(*usart)]);
        }
    }
}

/// plant: embedded defaults, or a file, then overrides; the seed feeds the encoders.
void read_plant(const Ctx& top, const YAML::Node& root, Scenario& s) {
    YAML::Node plant_yaml = default_plant_yaml();
    std::string plant_source = top.file().string() + " (plant)";
    if (root["plant"]) {
        const Ctx c = top.at(root["plant"], "plant");
        c.keys({"file", "overrides"});
        if (c.has("file")) {
            s.plant_file = existing_file(c.child("file"));
            plant::load_robot_params(*s.plant_file);  // its own messages name its file and line
            plant_yaml = YAML::LoadFile(s.plant_file->string());
        }
        if (c.has("overrides")) {
            const Ctx o = c.child("overrides");
            if (!o.node().IsMap()) o.fail("expected a mapping like {motor1: {resistance_ohm: 6.0}}");
            merge_plant_yaml(plant_yaml, o.node());
        }
    }
    seed_plant_yaml(plant_yaml, s.seed);
    try {
        YAML::Emitter e;
        e << plant_yaml;
        s.plant = plant::parse_robot_params(e.c_str(), plant_source);
    } catch (const std::exception& e) {
        top.at(root["plant"] ? root["plant"] : root, "plant").fail(e.what());
    }
}

/// steps: the list, each a mapping of one key (or a bare step that takes no value).
void read_steps(const Ctx& top, const YAML::Node& root, Scenario& s) {
    const Ctx steps = top.at(root["steps"], "steps");
    if (!root["steps"].IsSequence() || root["steps"].size() == 0) steps.fail("expected a non-empty list of steps");
    for (const auto& item : root["steps"]) {
        const Ctx sc = top.at(item, "steps[]");
        Step st;
        st.line = item.Mark().line + 1;
        // A step that takes no value may be written bare: `- reset`, `- expect-no-torn-reads`.
        if (item.IsScalar() && (item.Scalar() == "reset" || item.Scalar() == "expect-no-torn-reads")) {
            st.kind = item.Scalar();
            st.text = item.Scalar();
            st.action = yaml::parse_step(st.kind, top.at(YAML::Node(YAML::NodeType::Null), st.kind));
            s.steps.push_back(std::move(st));
            continue;
        }
        if (!item.IsMap() || item.size() != 1) {
            sc.fail("each step is a mapping with one key, e.g. - delay: 500ms (or a bare - reset / - expect-no-torn-reads)");
        }
        const std::string kind = item.begin()->first.Scalar();
        st.kind = kind;
        st.text = step_text(item);
        st.action = yaml::parse_step(kind, top.at(item.begin()->second, kind));
        s.steps.push_back(std::move(st));
    }
}

/// Each move-obstacle names an obstacle of the scenario's world.
void check_obstacle_names(const Scenario& s) {
    for (const Step& step : s.steps) {
        const auto* m = std::get_if<MoveObstacle>(&step.action);
        if (m == nullptr || plant::find_obstacle(s.world, m->name)) continue;
        std::string names;
        for (const std::string& n : s.world.obstacles) names += (names.empty() ? "" : ", ") + n;
        throw ScenarioError(fmt::format("{}:{}: key 'move-obstacle.name': the world has no obstacle '{}' ({})",
                                        s.file.string(), step.line, m->name,
                                        names.empty() ? "a wall is one when the world file gives it a name"
                                                      : "its obstacles: " + names));
    }
}

}  // namespace

Scenario parse_scenario(std::string_view yaml_text, const fs::path& file, const LoadOptions& options) {
    const YAML::Node root = load_root(yaml_text, file);
    Scenario s;
    s.file = file;
    read_board_file(root, file, s);
    const std::optional<PlatformioProject> pio = read_platformio(root, file, options, s);
    const hil::BoardDescription& board = hil::board_description(s.board.model);
    const Ctx top(file, root, "(top)", board, &s.board);
    read_world_file(root, file, s);
    top.keys({"name", "description", "version", "author", "firmware", "libraries", "board", "world", "plant", "pwm",
              "eeprom-timing", "seed", "fast-forward", "timeout", "serial", "eeprom", "steps"},
             {"steps", "timeout"});
    s.name = root["name"] ? top.at(root["name"], "name").str() : file.stem().string();
    if (root["description"]) s.description = top.at(root["description"], "description").str();
    read_firmware(top, root, options, pio.has_value(), s);
    read_libraries(top, root, options, s);
    read_run_settings(top, root, s);
    read_serial(top, root, board, s);
    if (root["eeprom"]) s.eeprom_preload = existing_file(top.at(root["eeprom"], "eeprom"));
    read_plant(top, root, s);
    read_steps(top, root, s);
    check_obstacle_names(s);
    return s;
}

Scenario load_scenario(const fs::path& file, const LoadOptions& options) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ScenarioError(fmt::format("{}: cannot read the scenario file", file.string()));
    std::ostringstream text;
    text << in.rdbuf();
    return parse_scenario(text.str(), file, options);
}

}  // namespace ddmr::tools::scenario
