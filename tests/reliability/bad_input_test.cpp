// Bad inputs to `ddmr-hil run` and `ddmr-hil scenario`, generated: broken
// firmware files, broken plant/board YAML, bad output folders. Each must give
// exit code 2, exactly one line on stderr that names the file (and the key or
// value), and leave nothing written.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

struct Case {
    std::string name;
    std::string file_name;  ///< written into the temp folder with `bytes`
    std::string bytes;
    std::string option;     ///< "--firmware", "--plant", "--board" or "--world"
    std::string expected;   ///< fragment of the one-line error
};

std::string read_bytes(const fs::path& p, std::size_t max = std::string::npos) {
    std::string s = read_text(p);
    return s.substr(0, std::min(max, s.size()));
}

/// A board file's first lines: the right wheel wired as the thesis robot's.
constexpr const char* kBoardHead =
    "wheels:\n  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n";

std::vector<Case> firmware_cases() {
    const std::string elf = read_bytes(firmware_elf());
    std::vector<Case> cases = {
        {"EmptyElf", "empty.elf", "", "--firmware", "empty file"},
        {"TruncatedHeader", "head.elf", elf.substr(0, 40), "--firmware", "head.elf"},
        {"TruncatedSections", "cut.elf", elf.substr(0, 600), "--firmware", "cut.elf"},
        {"TruncatedHalf", "half.elf", elf.substr(0, elf.size() / 2), "--firmware", "half.elf"},
        {"TextFile", "notes.elf", "this is not a firmware\n", "--firmware", "not an ELF"},
    };
    // Seeded random bytes, with and without the ELF magic in front.
    std::mt19937_64 rng(20261122);
    for (int k = 0; k < 4; ++k) {
        std::string bytes(static_cast<std::size_t>(64 + 977 * k), '\0');
        for (char& c : bytes) c = static_cast<char>(rng() & 0xFF);
        if (k % 2 == 1) bytes.replace(0, 4, "\x7f" "ELF");
        cases.push_back({"RandomBytes" + std::to_string(k), "random" + std::to_string(k) + ".elf", bytes,
                         "--firmware", "random" + std::to_string(k) + ".elf"});
    }
    // The build's Intel HEX, one checksum broken: refused as HEX (the HIL needs the ELF).
    std::string hex = read_bytes(firmware_elf().replace_extension(".hex"));
    const auto eol = hex.find('\n');
    hex[eol - 1] = hex[eol - 1] == '0' ? '1' : '0';
    cases.push_back({"IntelHexBadChecksum", "bad.hex", hex, "--firmware", "Intel HEX"});
    // A fuzz finding: section headers that pass the ELF checks, but simavr's
    // loader lays the program out past the flash (it would abort()).
    cases.push_back({"LoaderPastFlash", "past.elf",
                     read_bytes(source_dir() / "tests/fuzz/corpus/elf_loader/regression-loader-past-flash.elf"),
                     "--firmware", "past the ATmega328P's 32768-byte flash"});
    // Another: the symbol table's section is called .data, which simavr's
    // loader would read as program data (and crash on its nameless symbols).
    cases.push_back({"SymbolTableCalledData", "symtab.elf",
                     read_bytes(source_dir() / "tests/fuzz/corpus/elf_loader/regression-symtab-named-data.elf"),
                     "--firmware", "is called '.data' but has type 2, not program data"});
    return cases;
}

std::vector<Case> plant_cases() {
    return {
        {"Malformed", "p.yaml", "motor1: [1,\n", "--plant", "malformed YAML"},
        {"UnknownKey", "p.yaml", "motor1:\n  resistanse_ohm: 5\n", "--plant", "resistanse_ohm"},
        {"UnknownSection", "p.yaml", "motor3:\n  resistance_ohm: 5\n", "--plant", "motor3"},
        {"WrongType", "p.yaml", "motor1:\n  resistance_ohm: abc\n", "--plant", "resistance_ohm"},
        {"NaN", "p.yaml", "battery:\n  open_circuit_V: .nan\n", "--plant", "open_circuit_V"},
        {"Infinite", "p.yaml", "motor2:\n  inductance_H: .inf\n", "--plant", "inductance_H"},
        {"Negative", "p.yaml", "motor1:\n  inertia_kg_m2: -1e-7\n", "--plant", "inertia_kg_m2"},
        {"Zero", "p.yaml", "kinematics:\n  wheel_radius_right_m: 0\n", "--plant", "wheel_radius_right_m"},
        {"OldWiringInThePlantFile", "p.yaml", "board:\n  motor1: { enable_pin: 10 }\n", "--plant",
         "p.yaml:1:1: key 'board': the wiring is no longer part of the plant file"},
        {"NoSuchPin", "b.yaml", std::string(kBoardHead) + "  left: {motor: {driver: dir-pwm, PWM: 11, DIR: 20}, encoder: {type: single, OUT: 3}}\n",
         "--board", "b.yaml:3: key 'wheels.left.motor.DIR': '20' is not a pin"},
        {"NotAPwmPin", "b.yaml", std::string(kBoardHead) + "  left: {motor: {driver: dir-pwm, PWM: 4, DIR: 13}, encoder: {type: single, OUT: 3}}\n",
         "--board", "key 'wheels.left.motor.PWM': pin 4 has no timer output"},
        {"TwoFunctionsOnOnePin", "b.yaml", std::string(kBoardHead) + "  left: {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 12}}\n",
         "--board", "key 'wheels.left.encoder.OUT': pin 12 is already used by wheels.right.motor.DIR"},
        {"UnknownDriver", "b.yaml", std::string(kBoardHead) + "  left: {motor: {driver: l297, EN: 5}, encoder: {type: single, OUT: 3}}\n",
         "--board", "key 'wheels.left.motor.driver': unknown driver 'l297'"},
        {"MissingFile", "", "", "--plant", "missing.yaml"},
    };
}

/// World files (docs/world.md): a line with no width, a wall of zero length,
/// a polygon of two corners, a typo in a key, malformed YAML, no file.
std::vector<Case> world_cases() {
    return {
        {"LineWithoutWidth", "w.yaml", "lines:\n  - {points_m: [[0, 0], [1, 0]], width_m: 0}\n", "--world",
         "w.yaml:2: key 'lines[0].width_m': a line needs a width above 0"},
        {"WallOfZeroLength", "w.yaml", "walls:\n  - {from_m: [1, 1], to_m: [1, 1]}\n", "--world",
         "w.yaml:2: key 'walls[0]': a wall of zero length"},
        {"TwoCornerPolygon", "w.yaml", "walls:\n  - {polygon_m: [[0, 0], [1, 0]]}\n", "--world",
         "key 'walls[0].polygon_m': expected a list of at least 3 points"},
        {"UnknownWorldKey", "w.yaml", "lines:\n  - {points_m: [[0, 0], [1, 0]], widht_m: 0.02}\n", "--world",
         "key 'lines[0].widht_m': unknown key"},
        {"MalformedWorld", "w.yaml", "walls: [\n", "--world", "w.yaml:2: malformed YAML"},
        {"MissingWorld", "", "", "--world", "missing.yaml: cannot read the world file"},
    };
}

class BadInput : public ::testing::TestWithParam<Case> {};

void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

TEST_P(BadInput, RunRefusesWithOneLineAndWritesNothing) {
    const Case& c = GetParam();
    TempDir dir;
    fs::path input = dir / (c.file_name.empty() ? "missing.yaml" : c.file_name);
    if (!c.file_name.empty()) std::ofstream(input, std::ios::binary) << c.bytes;
    const fs::path out = dir / "out";
    const auto r = run_command(sh_quote(cli_path().string()) + " run " + c.option + " " + sh_quote(input.string()) +
                               " --out " + sh_quote(out.string()));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "exactly one line: " << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_TRUE(r.out.empty()) << r.out;
}

std::string case_name(const ::testing::TestParamInfo<Case>& param_info) { return param_info.param.name; }

INSTANTIATE_TEST_SUITE_P(Firmware, BadInput, ::testing::ValuesIn(firmware_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(Plant, BadInput, ::testing::ValuesIn(plant_cases()), case_name);
INSTANTIATE_TEST_SUITE_P(World, BadInput, ::testing::ValuesIn(world_cases()), case_name);

TEST(BadOutput, AFileOrAnUnwritableParentIsRefused) {
    TempDir dir;
    const fs::path file = dir / "afile";
    std::ofstream(file) << "keep me\n";
    for (const fs::path& out : {file, file / "sub", fs::path("/proc/ddmr-hil-out")}) {
        const auto r = run_command(sh_quote(cli_path().string()) + " run --out " + sh_quote(out.string()));
        EXPECT_EQ(r.exit_code, 2) << out << r.err;
        EXPECT_NE(r.err.find(out.string()), std::string::npos) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    }
    EXPECT_EQ(read_text(file), "keep me\n");
}

TEST(BadInputFirmware, TooBigForTheFlashIsRefused) {
    TempDir dir;
    const auto r = run_command(sh_quote(cli_path().string()) + " run --firmware " +
                               sh_quote((test_firmware_dir() / "too_big.elf").string()) + " --out " +
                               sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("does not fit the ATmega328P's 32768-byte flash"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(BadInputFirmware, ScenariosRefuseTheSameFirmwareFiles) {
    TempDir dir;
    const fs::path scenario = dir / "s.yaml";
    std::ofstream(scenario) << "timeout: 1s\nsteps:\n  - delay: 1ms\n";
    for (const auto& c : firmware_cases()) {
        const fs::path f = dir / c.file_name;
        std::ofstream(f, std::ios::binary) << c.bytes;
        const auto r = run_command(sh_quote(cli_path().string()) + " scenario " + sh_quote(scenario.string()) +
                                   " --firmware " + sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
        EXPECT_EQ(r.exit_code, 2) << c.name << ": " << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << c.name << ": " << r.err;
        EXPECT_FALSE(fs::exists(dir / "out")) << c.name;
    }
}

}  // namespace
}  // namespace ddmr::test
