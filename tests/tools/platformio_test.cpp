// Tests for tools/common/platformio_project and the Unity mode of `run`
// (issue 24): a project folder laid out as `pio run` leaves it
// (platformio.ini, src/, .pio/build/ENV/firmware.elf), run by
// `run --platformio` and by a scenario's `firmware: {platformio: ...}`; and
// `run --unity` as pio test's test_testing_command. PlatformIO itself is not
// installed: the ELFs are the project's test firmwares, put where pio puts
// its own.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include "common/platformio_project.hpp"
#include "common/unity_summary.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// A project with [env:robot] (board = `board`) and the ELF `elf` as its
/// build result, newer than its sources.
fs::path make_project(const TempDir& dir, const std::string& ini, const fs::path& elf, const std::string& env = "robot") {
    const fs::path p = dir / "project";
    fs::create_directories(p / "src");
    fs::create_directories(p / ".pio/build" / env);
    std::ofstream(p / "platformio.ini") << ini;
    std::ofstream(p / "src/main.cpp") << "// the sketch pio built\n";
    const auto sources_time = fs::last_write_time(p / "src/main.cpp");
    fs::copy_file(elf, p / ".pio/build" / env / "firmware.elf");
    fs::last_write_time(p / ".pio/build" / env / "firmware.elf", sources_time + std::chrono::seconds(10));
    return p;
}

constexpr const char* kUnoIni = R"(; PlatformIO Project Configuration File
[platformio]
default_envs = robot

[env]
framework = arduino
build_flags =
    -D ROBOT=1
    -Wall

[env:robot]
platform = atmelavr
board = uno
board_build.f_cpu = 16000000L
test_testing_command =
    ddmr-hil
    run
    --unity
)";

TEST(PlatformioProject, ReadsTheBoardAndTheElf) {
    TempDir dir;
    const fs::path p = make_project(dir, kUnoIni, firmware_elf());
    const auto project = tools::load_platformio_project(p, "");
    EXPECT_EQ(project.env, "robot");
    EXPECT_EQ(project.board_id, "uno");
    EXPECT_EQ(project.board, hil::BoardModel::uno);
    EXPECT_EQ(project.elf, p / ".pio/build/robot/firmware.elf");
    // extends and [env]: the board comes from the section extended.
    std::ofstream(p / "platformio.ini") << "[common]\nboard = megaatmega2560\n[env:m]\nextends = common\n";
    fs::create_directories(p / ".pio/build/m");
    fs::copy_file(test_firmware_dir() / "mega_l298n_int45.elf", p / ".pio/build/m/firmware.elf");
    fs::last_write_time(p / ".pio/build/m/firmware.elf", fs::last_write_time(p / "platformio.ini") + std::chrono::seconds(5));
    EXPECT_EQ(tools::load_platformio_project(p, "m").board, hil::BoardModel::mega2560);
    // The shipped example (firmware/examples/platformio): its default environment, the Uno.
    fs::copy_file(source_dir() / "firmware/examples/platformio/platformio.ini", p / "platformio.ini",
                  fs::copy_options::overwrite_existing);
    fs::create_directories(p / ".pio/build/uno");
    fs::copy_file(firmware_elf(), p / ".pio/build/uno/firmware.elf");
    fs::last_write_time(p / ".pio/build/uno/firmware.elf",
                        fs::last_write_time(p / "platformio.ini") + std::chrono::seconds(5));
    const auto example = tools::load_platformio_project(p, "");
    EXPECT_EQ(example.env, "uno");
    EXPECT_EQ(example.board, hil::BoardModel::uno);
    EXPECT_EQ(tools::platformio_board("nanoatmega328new"), hil::BoardModel::nano);
    EXPECT_EQ(tools::platformio_board("pro8MHzatmega328"), hil::BoardModel::pro_mini_8mhz);
    EXPECT_FALSE(tools::platformio_board("esp32dev").has_value());
}

TEST(PlatformioProject, RefusesWhatItCannotRunInOneLine) {
    TempDir dir;
    const fs::path p = make_project(dir, kUnoIni, firmware_elf());
    const auto refused = [&](const std::string& ini, const std::string& env, const std::string& named) {
        std::ofstream(p / "platformio.ini") << ini;
        fs::last_write_time(p / ".pio/build/robot/firmware.elf",
                            fs::last_write_time(p / "platformio.ini") + std::chrono::seconds(5));
        try {
            tools::load_platformio_project(p, env);
            ADD_FAILURE() << "accepted: " << ini;
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(named), std::string::npos) << e.what();
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
        }
    };
    refused("[env:robot]\nboard = esp32dev\n", "", "board = esp32dev: ddmr-hil models uno");
    refused("[env:robot]\nboard = uno\nboard_build.f_cpu = 8000000L\n", "", "the Arduino Uno runs at 16000000 Hz");
    refused("[env:robot]\nboard = uno\nboard_build.mcu = atmega168\n", "", "board_build.mcu = atmega168");
    refused("[env:robot]\nboard = uno\n", "other", "no [env:other] (the environments: robot)");
    refused("[env:a]\nboard = uno\n[env:robot]\nboard = uno\n", "", "give the environment");
    refused("[env:robot]\nplatform = atmelavr\n", "", "no board = ...");
    refused("[env:robot]\nboard = ${common.board}\n", "", "${common.board}: there is no board in [common]");
}

TEST(PlatformioProject, RefusesAMissingOrStaleElf) {
    TempDir dir;
    const fs::path p = make_project(dir, kUnoIni, firmware_elf());
    fs::create_directories(p / "lib/Drive");
    std::ofstream(p / "lib/Drive/Drive.cpp") << "// edited after the build\n";
    fs::last_write_time(p / "lib/Drive/Drive.cpp",
                        fs::last_write_time(p / ".pio/build/robot/firmware.elf") + std::chrono::seconds(60));
    try {
        tools::load_platformio_project(p, "robot");
        ADD_FAILURE() << "a stale ELF was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("older than " + (p / "lib/Drive/Drive.cpp").string() +
                                             ": build it again with `pio run -e robot`"),
                  std::string::npos)
            << e.what();
    }
    // The Uno's ELF where the environment says Mega: refused, saying what to do.
    std::ofstream(p / "platformio.ini") << "[env:robot]\nboard = megaatmega2560\n";
    fs::remove(p / "lib/Drive/Drive.cpp");
    fs::last_write_time(p / ".pio/build/robot/firmware.elf",
                        fs::last_write_time(p / "platformio.ini") + std::chrono::seconds(5));
    try {
        tools::load_platformio_project(p, "robot");
        ADD_FAILURE() << "an ELF for another MCU was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("not a program for the ATmega2560 of [env:robot] (board = "
                                             "megaatmega2560): build it again with `pio run -e robot`, or correct "
                                             "board ="),
                  std::string::npos)
            << e.what();
    }
    fs::remove(p / ".pio/build/robot/firmware.elf");
    try {
        tools::load_platformio_project(p, "robot");
        ADD_FAILURE() << "a missing ELF was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("no ELF for [env:robot]: build it first with `pio run -e robot`"),
                  std::string::npos)
            << e.what();
    }
}

TEST(PlatformioProject, RunAndScenarioUseTheProjectsElfAndBoard) {
    TempDir dir;
    const fs::path p = make_project(dir, kUnoIni, firmware_elf());
    // run --platformio: the reference sketch, built by "pio", on the Uno it names.
    const auto r = run_command(sh_quote(cli_path().string()) + " run -q --platformio " + sh_quote(p.string()) +
                               " --seconds 1 --out " + sh_quote((dir / "out").string()));
    ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
    const json s = json::parse(read_text(dir / "out/summary.json"));
    EXPECT_EQ(s["firmware"]["path"], (p / ".pio/build/robot/firmware.elf").string());
    EXPECT_EQ(s["firmware_source"]["env"], "robot");
    EXPECT_EQ(s["firmware_source"]["board_id"], "uno");
    EXPECT_EQ(s["board"]["name"], "uno");
    // --platformio with --firmware, or a board that contradicts the project: refused.
    const auto both = run_command(sh_quote(cli_path().string()) + " run --platformio " + sh_quote(p.string()) +
                                  " --firmware " + sh_quote(firmware_elf().string()) + " --out " +
                                  sh_quote((dir / "o2").string()));
    EXPECT_EQ(both.exit_code, 2);
    EXPECT_NE(both.err.find("give one of --firmware, --sketch and --platformio"), std::string::npos) << both.err;
    const auto mega = run_command(sh_quote(cli_path().string()) + " run --platformio " + sh_quote(p.string()) +
                                  " --board-name mega2560 --out " + sh_quote((dir / "o3").string()));
    EXPECT_EQ(mega.exit_code, 2);
    EXPECT_NE(mega.err.find("--board-name mega2560: " + (p / "platformio.ini").string() +
                            "'s [env:robot] builds for board = uno (uno)"),
              std::string::npos)
        << mega.err;
    // A board file for another board: said about the board file.
    const auto nano = run_command(sh_quote(cli_path().string()) + " run --platformio " + sh_quote(p.string()) +
                                  " --board " +
                                  sh_quote((source_dir() / "firmware/examples/drv8833_nano_mirrored/board.yaml").string()) +
                                  " --out " +
                                  sh_quote((dir / "o4").string()));
    EXPECT_EQ(nano.exit_code, 2);
    EXPECT_NE(nano.err.find("'s [env:robot] builds for board = uno (uno): the board file "), std::string::npos)
        << nano.err;
    EXPECT_NE(nano.err.find(" is for the Arduino Nano (ATmega328P) (board: nano); put board: uno in the board file"),
              std::string::npos)
        << nano.err;
    // The project's platformio.ini names the project as well as its folder.
    const auto ini = run_command(sh_quote(cli_path().string()) + " run -q --platformio " +
                                 sh_quote((p / "platformio.ini").string()) + " --seconds 0.1 --out " +
                                 sh_quote((dir / "o5").string()));
    EXPECT_EQ(ini.exit_code, 0) << ini.err;
    EXPECT_FALSE(fs::exists(dir / "o2"));
    EXPECT_FALSE(fs::exists(dir / "o3"));
    // A scenario beside the project names it (relative to the scenario file).
    std::ofstream(dir / "s.yaml") << "name: pio\ntimeout: 6s\nfirmware: { platformio: project, env: robot }\n"
                                     "steps:\n  - write-serial: \"1\"\n  - wait-serial: \"0.6m\"\n";
    const auto sc = run_command(sh_quote(cli_path().string()) + " scenario " + sh_quote((dir / "s.yaml").string()) +
                                " --out " + sh_quote((dir / "sout").string()));
    ASSERT_EQ(sc.exit_code, 0) << sc.out << sc.err;
    const json j = json::parse(read_text(dir / "sout/pio/result.json"));
    EXPECT_EQ(j["platformio"]["env"], "robot");
    EXPECT_EQ(j["firmware"], (p / ".pio/build/robot/firmware.elf").string());
}

TEST(UnitySummaryWatch, EndsAfterTheOkOrFailLine) {
    tools::UnitySummaryWatch w;
    int ended = 0;
    for (const char c : std::string("t.c:3:a:PASS\n3 Tests in a text line\n-----------------------\n"
                                    "3 Tests 1 Failures 0 Ignored \r\nFAIL\r\nmore\n")) {
        ended += w.feed(c) ? 1 : 0;
    }
    EXPECT_EQ(ended, 1);
    ASSERT_TRUE(w.summary().has_value());
    EXPECT_EQ(w.summary()->tests, 3U);
    EXPECT_EQ(w.summary()->failures, 1U);
    EXPECT_EQ(w.summary()->ignored, 0U);
    EXPECT_FALSE(w.summary()->ok);
    // A counts line followed by something else is not Unity's summary.
    tools::UnitySummaryWatch v;
    for (const char c : std::string("2 Tests 0 Failures 0 Ignored\nnot the end\nOK\n")) EXPECT_FALSE(v.feed(c));
    EXPECT_FALSE(v.summary().has_value());
}

TEST(UnityRun, TheExitCodeFollowsUnitysVerdictAndStdoutIsTheUart) {
    TempDir dir;
    for (const std::string variant : {"ok", "fail"}) {
        const fs::path out = dir / variant;
        const auto r = run_command(sh_quote(cli_path().string()) + " run -q --unity --firmware " +
                                   sh_quote((test_firmware_dir() / ("unity_fixture_" + variant + ".elf")).string()) +
                                   " --seconds 5 --out " + sh_quote(out.string()));
        EXPECT_EQ(r.exit_code, variant == "ok" ? 0 : 1) << r.out << r.err;
        // stdout: the firmware's lines as sent, up to Unity's last line.
        EXPECT_EQ(r.out.rfind("test/test_main.cpp:21:test_wheel_distance:PASS\r\n", 0), 0U) << r.out;
        const std::string last = variant == "ok" ? "0 Failures 0 Ignored \r\nOK\r\n" : "1 Failures 0 Ignored \r\nFAIL\r\n";
        EXPECT_EQ(r.out.substr(r.out.size() - last.size()), last) << r.out;
        EXPECT_EQ(r.out.find("after the summary"), std::string::npos);
        EXPECT_NE(r.err.find(variant == "ok" ? "Unity: 3 tests, 0 failures, 0 ignored: OK"
                                             : "Unity: 3 tests, 1 failures, 0 ignored: FAIL"),
                  std::string::npos)
            << r.err;
        const json s = json::parse(read_text(out / "summary.json"));
        EXPECT_EQ(s["unity"]["failures"], variant == "ok" ? 0 : 1);
        EXPECT_EQ(s["unity"]["complete"], true);
        EXPECT_EQ(s["exit_reason"], "report_complete");
        EXPECT_LT(s["sim_seconds"].get<double>(), 0.5);  // ended by the summary, not by --seconds
    }
    // A firmware that never prints the summary: the time limit, exit 3, said why.
    const auto never = run_command(sh_quote(cli_path().string()) + " run -q --unity --firmware " +
                                   sh_quote((test_firmware_dir() / "echo_fixture.elf").string()) +
                                   " --seconds 0.2 --out " + sh_quote((dir / "never").string()));
    EXPECT_EQ(never.exit_code, 3);
    EXPECT_NE(never.err.find("Unity's summary ('N Tests N Failures N Ignored', then OK or FAIL) never came"),
              std::string::npos)
        << never.err;
    EXPECT_EQ(json::parse(read_text(dir / "never/summary.json"))["unity"], json({{"complete", false}}));
}

}  // namespace
}  // namespace ddmr::test
