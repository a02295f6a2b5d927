// Tests for tools/common/sketch_build and arduino_libraries (issue 24): the
// example sketch firmware/examples/library_odometry includes two libraries
// Arduino does not ship (WheelOdometry: library.properties and src/;
// SoftStart: flat, legacy). It must build and run from each place Arduino
// users keep libraries, and a missing one is one line, exit 2, nothing
// written. Each test has its own HOME and cache (nothing of the machine's
// ~/Arduino is seen). Every build is a real arduino-builder run (labelled
// slow: not repeated under the sanitizers, where only arduino-builder's time
// would grow).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/arduino_libraries.hpp"
#include "hil/elf_image.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

fs::path example() { return source_dir() / "firmware/examples/library_odometry"; }

/// The example's sketch folder copied into `dir` (a sketch of the user's own).
fs::path copy_sketch(const TempDir& dir) {
    const fs::path sketch = dir / "library_odometry";
    fs::create_directories(sketch);
    fs::copy_file(example() / "library_odometry/library_odometry.ino", sketch / "library_odometry.ino");
    return sketch / "library_odometry.ino";
}

/// HOME and the cache inside the test's folder.
std::string env_of(const TempDir& dir) {
    fs::create_directories(dir / "home");
    return "env -u ARDUINO_DIRECTORIES_USER HOME=" + sh_quote((dir / "home").string()) +
           " XDG_CACHE_HOME=" + sh_quote((dir / "cache").string()) + " ";
}

/// `run --sketch` for 2 simulated s (the drive, the brake and the report).
ProcessResult run_sketch(const TempDir& dir, const fs::path& ino, const std::string& more) {
    return run_command(env_of(dir) + sh_quote(cli_path().string()) + " run -q --sketch " + sh_quote(ino.string()) +
                       " --board " + sh_quote((example() / "board.yaml").string()) + " --seconds 2 --out " +
                       sh_quote((dir / "out").string()) + more);
}

/// The report the sketch prints, and the libraries summary.json names.
void expect_drove_with_both_libraries(const TempDir& dir) {
    const std::string uart = read_text(dir / "out/uart.txt");
    EXPECT_NE(uart.find("library_odometry ready: 500 mm = 949 counts"), std::string::npos) << uart;
    EXPECT_NE(uart.find("stopped: left 5"), std::string::npos) << uart;
    const json s = json::parse(read_text(dir / "out/summary.json"));
    const json& libs = s["firmware_source"]["libraries"];
    ASSERT_EQ(libs.size(), 2U) << s["firmware_source"].dump(1);
    EXPECT_EQ(libs[0]["name"], "WheelOdometry");
    EXPECT_EQ(libs[0]["version"], "1.0.0");
    EXPECT_EQ(libs[1]["name"], "SoftStart");
    EXPECT_EQ(libs[1]["version"], "");  // legacy: no library.properties
}

TEST(SketchLibraries, FromALibrariesOption) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    const auto r = run_sketch(dir, ino, " --libraries " + sh_quote((example() / "libraries").string()));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_drove_with_both_libraries(dir);
    // Said on stderr, with the versions and folders.
    EXPECT_NE(r.err.find("libraries WheelOdometry 1.0.0 (" + (example() / "libraries/WheelOdometry").string() + ")"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("SoftStart (legacy, "), std::string::npos) << r.err;
    const json s = json::parse(read_text(dir / "out/summary.json"));
    EXPECT_EQ(s["firmware_source"]["from_cache"], false);
    // The CMake helper (add_arduino_sketch ... LIBRARIES) builds the same program.
    const auto built = hil::ElfImage::read(s["firmware"]["path"].get<std::string>());
    const auto by_cmake = hil::ElfImage::read(test_firmware_dir() / "library_odometry.elf");
    EXPECT_EQ(built.memory_use().flash_bytes(), by_cmake.memory_use().flash_bytes());
    EXPECT_EQ(built.memory_use().ram_bytes(), by_cmake.memory_use().ram_bytes());
    // The same sketch and folders again: the cached ELF.
    const auto again = run_sketch(dir, ino, " --libraries " + sh_quote((example() / "libraries").string()));
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(json::parse(read_text(dir / "out/summary.json"))["firmware_source"]["from_cache"], true);
}

TEST(SketchLibraries, FromTheSketchbookOfHome) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    fs::create_directories(dir / "home/Arduino");
    fs::copy(example() / "libraries", dir / "home/Arduino/libraries", fs::copy_options::recursive);
    const auto r = run_sketch(dir, ino, "");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_drove_with_both_libraries(dir);
    const json s = json::parse(read_text(dir / "out/summary.json"));
    EXPECT_EQ(s["firmware_source"]["libraries"][0]["folder"],
              (dir / "home/Arduino/libraries/WheelOdometry").string());
    // Another library installed beside them: another build (it could shadow one).
    fs::create_directories(dir / "home/Arduino/libraries/Unrelated");
    std::ofstream(dir / "home/Arduino/libraries/Unrelated/Unrelated.h") << "#pragma once\n";
    const auto installed = run_sketch(dir, ino, "");
    ASSERT_EQ(installed.exit_code, 0) << installed.err;
    EXPECT_EQ(json::parse(read_text(dir / "out/summary.json"))["firmware_source"]["from_cache"], false);
    // A library changed since the build: built again, not the stale ELF.
    std::ofstream(dir / "home/Arduino/libraries/SoftStart/SoftStart.cpp", std::ios::app) << "\n// edited\n";
    const auto again = run_sketch(dir, ino, "");
    ASSERT_EQ(again.exit_code, 0) << again.err;
    EXPECT_EQ(json::parse(read_text(dir / "out/summary.json"))["firmware_source"]["from_cache"], false);
}

TEST(SketchLibraries, FromTheSketchsOwnSrcFolder) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    // Both libraries shipped inside the sketch: arduino-builder also compiles
    // src/ as the sketch's code, so the build must not define them twice.
    fs::copy(example() / "libraries", ino.parent_path() / "src", fs::copy_options::recursive);
    const auto r = run_sketch(dir, ino, "");
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    expect_drove_with_both_libraries(dir);
}

TEST(SketchLibraries, AScenarioNamesItsLibrariesAndTheSketchbookVariable) {
    TempDir dir;
    // The shipped example (libraries: [libraries]) runs and passes ...
    const auto r = run_command(env_of(dir) + sh_quote(cli_path().string()) + " scenario " +
                               sh_quote((example() / "scenario.yaml").string()) + " --out " +
                               sh_quote((dir / "out").string()));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json j = json::parse(read_text(dir / "out/library_odometry/result.json"));
    ASSERT_EQ(j["sketch"]["libraries"].size(), 2U) << j["sketch"].dump(1);
    EXPECT_EQ(j["sketch"]["libraries"][0]["folder"], (example() / "libraries/WheelOdometry").string());
    // ... and $ARDUINO_DIRECTORIES_USER/libraries is arduino-cli's sketchbook.
    const fs::path user = dir / "arduino-user";
    fs::create_directories(user);
    fs::copy(example() / "libraries", user / "libraries", fs::copy_options::recursive);
    const fs::path ino = copy_sketch(dir);
    const auto v = run_command("ARDUINO_DIRECTORIES_USER=" + sh_quote(user.string()) + " HOME=" +
                               sh_quote((dir / "home").string()) + " XDG_CACHE_HOME=" +
                               sh_quote((dir / "cache").string()) + " " + sh_quote(cli_path().string()) +
                               " run -q --sketch " + sh_quote(ino.string()) + " --board " +
                               sh_quote((example() / "board.yaml").string()) + " --seconds 2 --out " +
                               sh_quote((dir / "out2").string()));
    ASSERT_EQ(v.exit_code, 0) << v.err;
    const json s = json::parse(read_text(dir / "out2/summary.json"));
    EXPECT_EQ(s["firmware_source"]["libraries"][0]["folder"], (user / "libraries/WheelOdometry").string());
}

TEST(SketchLibraries, AMissingLibraryIsOneLineAndNothingIsWritten) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    const auto r = run_sketch(dir, ino, "");
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    // The compiler's first missing header, at the sketch's line 13.
    const std::string expected_start = "ddmr-hil run: error: " + ino.string() + ":12: 'WheelOdometry.h' not found in";
    EXPECT_EQ(r.err.rfind(expected_start, 0), 0U) << r.err;
    EXPECT_NE(r.err.find((dir / "home/Arduino/libraries").string() + " (no such folder)"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("; install the library into " + (dir / "home/Arduino/libraries").string() +
                         " or pass --libraries DIR\n"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
    // The scenario command: the same line, before any output folder.
    std::ofstream(dir / "s.yaml") << "timeout: 1s\nfirmware: { sketch: library_odometry/library_odometry.ino }\n"
                                     "steps:\n  - delay: 1ms\n";
    const auto s = run_command(env_of(dir) + sh_quote(cli_path().string()) + " scenario " +
                               sh_quote((dir / "s.yaml").string()) + " --out " + sh_quote((dir / "sout").string()));
    EXPECT_EQ(s.exit_code, 2) << s.err;
    EXPECT_NE(s.err.find(":12: 'WheelOdometry.h' not found in"), std::string::npos) << s.err;
    EXPECT_FALSE(fs::exists(dir / "sout"));
}

TEST(SketchLibraries, ANamedFolderMustExist) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    const auto r = run_sketch(dir, ino, " --libraries " + sh_quote((dir / "nowhere").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("--libraries"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
    // A library itself, not a folder of libraries (a common slip): said so, with its parent.
    for (const char* lib : {"WheelOdometry", "SoftStart"}) {
        const auto one = run_sketch(dir, ino, " --libraries " + sh_quote((example() / "libraries" / lib).string()));
        EXPECT_EQ(one.exit_code, 2) << lib;
        EXPECT_NE(one.err.find("a library itself"), std::string::npos) << one.err;
        EXPECT_NE(one.err.find("give the folder that holds it (" + (example() / "libraries").string() + ")"),
                  std::string::npos)
            << one.err;
    }
    std::ofstream(dir / "s.yaml") << "timeout: 1s\nfirmware: { sketch: library_odometry/library_odometry.ino }\n"
                                     "libraries: [nowhere]\nsteps:\n  - delay: 1ms\n";
    const auto s = run_command(env_of(dir) + sh_quote(cli_path().string()) + " scenario " +
                               sh_quote((dir / "s.yaml").string()) + " --out " + sh_quote((dir / "sout").string()));
    EXPECT_EQ(s.exit_code, 2);
    EXPECT_NE(s.err.find("s.yaml:3: key 'libraries[0]': 'nowhere' is not a folder"), std::string::npos) << s.err;
    fs::copy(example() / "libraries/SoftStart", dir / "SoftStart", fs::copy_options::recursive);
    std::ofstream(dir / "s.yaml") << "timeout: 1s\nfirmware: { sketch: library_odometry/library_odometry.ino }\n"
                                     "libraries: [SoftStart]\nsteps:\n  - delay: 1ms\n";
    const auto l = run_command(env_of(dir) + sh_quote(cli_path().string()) + " scenario " +
                               sh_quote((dir / "s.yaml").string()) + " --out " + sh_quote((dir / "sout").string()));
    EXPECT_EQ(l.exit_code, 2);
    EXPECT_NE(l.err.find("'SoftStart' is a library itself (it has SoftStart.cpp at its top)"), std::string::npos)
        << l.err;
}

TEST(SketchLibraries, TheSketchsOwnCopyWinsAndTheOtherIsSaid) {
    TempDir dir;
    const fs::path ino = copy_sketch(dir);
    // The same two libraries in the sketch's src/, a named folder and the sketchbook:
    // the sketch's own copies are used (the first folder of docs/firmware.md's list).
    fs::copy(example() / "libraries", ino.parent_path() / "src", fs::copy_options::recursive);
    fs::create_directories(dir / "home/Arduino");
    fs::copy(example() / "libraries", dir / "home/Arduino/libraries", fs::copy_options::recursive);
    fs::copy(example() / "libraries", dir / "named", fs::copy_options::recursive);
    const auto r = run_sketch(dir, ino, " --libraries " + sh_quote((dir / "named").string()));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json s = json::parse(read_text(dir / "out/summary.json"));
    EXPECT_EQ(s["firmware_source"]["libraries"][0]["folder"], (ino.parent_path() / "src/WheelOdometry").string());
    // arduino-builder's choice among the copies is said, on stderr and in summary.json.
    const std::string said = "warning: 'WheelOdometry.h' is in 3 libraries: used " +
                             (ino.parent_path() / "src/WheelOdometry").string();
    EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
    EXPECT_FALSE(s["firmware_source"]["warnings"].empty());
    // Without the sketch's copies, the named folder's beat the sketchbook's.
    fs::remove_all(ino.parent_path() / "src");
    const auto named = run_sketch(dir, ino, " --libraries " + sh_quote((dir / "named").string()));
    ASSERT_EQ(named.exit_code, 0) << named.err;
    EXPECT_EQ(json::parse(read_text(dir / "out/summary.json"))["firmware_source"]["libraries"][0]["folder"],
              (dir / "named/WheelOdometry").string());
    // A sketch folder names its sketch.
    const auto folder = run_sketch(dir, ino.parent_path(), " --libraries " + sh_quote((dir / "named").string()));
    EXPECT_EQ(folder.exit_code, 0) << folder.err;
}

TEST(SketchLibraries, ACompileErrorIsShownNotOnlyLogged) {
    TempDir dir;
    fs::create_directories(dir / "bad");
    std::ofstream(dir / "bad/bad.ino") << "void setup() { Serial.begin(9600) }\nvoid loop() {}\n";
    const auto r = run_sketch(dir, dir / "bad/bad.ino", "");
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("arduino-builder failed (exit 1): " + (dir / "bad/bad.ino").string() + ":1:"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("error: expected"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("its whole output: "), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(dir / "out"));
}

// The log lines arduino-builder 1.3.25 prints (-verbose), and avr-gcc's.
TEST(ArduinoLibraries, ReadsWhatTheBuilderAndTheCompilerSay) {
    const auto used = tools::parse_used_libraries(
        "Linking everything together...\n"
        "Using library Servo at version 1.1.8 in folder: /home/u/Arduino/libraries/Servo \n"
        "Using library Twice in folder: /l/Twice (legacy)\n"
        "Sketch uses 1706 bytes (5%) of program storage space.\n");
    ASSERT_EQ(used.size(), 2U);
    EXPECT_EQ(used[0].name, "Servo");
    EXPECT_EQ(used[0].version, "1.1.8");
    EXPECT_EQ(used[0].folder, "/home/u/Arduino/libraries/Servo");
    EXPECT_EQ(used[1].name, "Twice");
    EXPECT_EQ(used[1].version, "");
    EXPECT_EQ(used[1].folder, "/l/Twice");
    const auto missing = tools::find_missing_header(
        "\"/usr/bin/avr-g++\" -c ...\n/tmp/sk/sk.ino:3:19: fatal error: Servo.h: No such file or directory\n"
        "compilation terminated.\n");
    ASSERT_TRUE(missing.has_value());
    EXPECT_EQ(missing->file, "/tmp/sk/sk.ino");
    EXPECT_EQ(missing->line, 3);
    EXPECT_EQ(missing->header, "Servo.h");
    EXPECT_FALSE(tools::find_missing_header("sk.ino:3:1: error: 'x' was not declared in this scope\n"));
    EXPECT_EQ(tools::first_build_error("Compiling sketch...\n/s/sk.ino:3:1: error: 'x' was not declared\n"),
              "/s/sk.ino:3:1: error: 'x' was not declared");
    EXPECT_EQ(tools::first_build_error("sketch.cpp.o: In function `loop':\nsk.ino:5: undefined reference to `f()'\n"),
              "sk.ino:5: undefined reference to `f()'");
    EXPECT_FALSE(tools::first_build_error("Sketch uses 1706 bytes (5%) of program storage space.\n"));
    const auto warnings = tools::builder_warnings(
        "Multiple libraries were found for \"Lib.h\"\n Used: /b/Lib\n Not used: /a/Lib\nUsing library Lib at "
        "version 1.0.2 in folder: /b/Lib \nWARNING: library Lib claims to run on (esp32) architecture(s) and may "
        "be incompatible with your current board which runs on (avr) architecture(s).\n");
    ASSERT_EQ(warnings.size(), 2U);
    EXPECT_EQ(warnings[0], "'Lib.h' is in 2 libraries: used /b/Lib, not used /a/Lib");
    EXPECT_EQ(warnings[1].rfind("library Lib claims to run on (esp32)", 0), 0U) << warnings[1];
}

}  // namespace
}  // namespace ddmr::test
