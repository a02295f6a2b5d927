// Tests for tools/scenario_command and tools/scenario/scenario_runner: short
// scenarios on the reference firmware, run by the real command line.
// The sketch answers its case byte after setup()'s delay(5000): "0.6m" for
// '1', "X" for anything else.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

#include "hil/elf_image.hpp"
#include "support/process.hpp"
#include "support/scenario_cli.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using nlohmann::json;

TEST(ScenarioCommand, StartsTheCircleAndSeesThePins) {
    TempDir dir;
    const auto f = write_text(dir, "start.yaml", R"(name: start
timeout: 8s
steps:
  - delay: 100ms
  - expect-pin: { pin: 12, value: 0 }
  - write-serial: "1"
  - wait-serial: { text: "0.6m", timeout: 6s }
  - expect-pin: { pin: 12, value: 1 }
  - expect-pin: { pin: 13, value: 1 }
  - delay: 50ms
  - expect-pwm: { pin: 10, duty: 0.91, tol: 0.05 }   # the control law's first demands
  - expect-var: { name: Count1, type: int32, op: ">", value: 0 }
)");
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("PASS  start"), std::string::npos) << r.out;
    const json j = result_of(dir / "out/start");
    EXPECT_EQ(j["verdict"], "pass");
    ASSERT_EQ(j["steps"].size(), 9U);
    // setup() ends with delay(5000): the answer comes about 5 s after boot.
    const double t_answer = j["steps"][3]["t_s"].get<double>();
    EXPECT_GT(t_answer, 5.0);
    EXPECT_LT(t_answer, 5.1);
    EXPECT_EQ(read_text(dir / "out/start/uart.txt"), "0.6m\r\n");
    EXPECT_FALSE(std::filesystem::exists(dir / "out/start/failure_window.vcd"));
}

TEST(ScenarioCommand, WaitsForAndChecksPlantSignals) {
    TempDir dir;
    const auto f = write_text(dir, "signals.yaml", R"(name: signals
timeout: 8s
steps:
  - delay: 100ms
  - write-serial: "1"
  - expect: { signal: left.wheel_rad_s, op: "==", value: 0 }      # setup() still waits
  - wait-until: { signal: x_m, op: ">=", value: 0.05, timeout: 7s }
  - expect: { signal: left.wheel_rad_s, between: [0.5, 100] }
  - expect: { signal: right.wheel_rad_s, between: [0.5, 100] }
  - stall: { motor: left, for: 50ms }
  - delay: 20ms
  - expect: { signal: left.wheel_rad_s, op: "==", value: 0 }       # left = motor 2: held
  - expect: { signal: wheel2_rad_s, op: "==", value: 0 }
  - expect: { signal: right.wheel_rad_s, op: ">", value: 0.5 }
)");
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    const json j = result_of(dir / "out/signals");
    EXPECT_EQ(j["verdict"], "pass") << j.dump(1);
    ASSERT_EQ(j["steps"].size(), 11U);
    // The robot starts after setup()'s delay(5000) and reaches 5 cm soon after.
    const double t_reached = j["steps"][3]["t_s"].get<double>();
    EXPECT_GT(t_reached, 5.0);
    EXPECT_LT(t_reached, 6.0);
    EXPECT_NE(j["steps"][3]["message"].get<std::string>().find("x_m = 0.05"), std::string::npos) << j["steps"][3];
    EXPECT_NE(j["steps"][4]["message"].get<std::string>().find("left.wheel_rad_s = "), std::string::npos);
}

TEST(ScenarioCommand, APushOverTimeTurnsTheRobotEvenly) {
    // The thesis robot at rest (case 1 not started: both bridges coasting)
    // turned 0.4 rad evenly over 200 ms, a piece at each 62.5 us coupling
    // step: halfway 0.2 rad (1600 of 3200 pieces), at the end all of it and
    // no more after. The wheels do not turn: no encoder edges.
    TempDir dir;
    const auto f = write_text(dir, "push_over.yaml", R"(name: push_over
timeout: 2s
steps:
  - delay: 100ms
  - push: { dtheta_rad: 0.4, over: 200ms }
  - delay: 100ms
  - expect: { signal: theta_rad, between: [0.1999, 0.2001] }
  - delay: 100ms
  - expect: { signal: theta_rad, between: [0.3999, 0.4001] }
  - delay: 100ms
  - expect: { signal: theta_rad, between: [0.3999, 0.4001] }
  - expect: { signal: edges1, op: "==", value: 0 }
  - expect: { signal: edges2, op: "==", value: 0 }
)");
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(result_of(dir / "out/push_over")["verdict"], "pass");
}

TEST(ScenarioCommand, PlantSignalFailuresSayTheValueSeen) {
    TempDir dir;
    const auto slow = write_text(dir, "far.yaml", R"(name: far
timeout: 8s
steps:
  - delay: 100ms
  - write-serial: "1"
  - wait-until: { signal: x_m, op: ">=", value: 5, timeout: 5.5s }
)");
    const auto fast = write_text(dir, "fast.yaml", R"(name: fast
timeout: 8s
steps:
  - delay: 100ms
  - write-serial: "1"
  - wait-until: { signal: right.edges, op: ">", value: 100, timeout: 6s }
  - expect: { signal: left.wheel_rad_s, between: [100, 200] }
)");
    const auto r = scenario(sh_quote(slow.string()) + " " + sh_quote(fast.string()) + " --out " +
                            sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const json a = result_of(dir / "out/far");
    EXPECT_EQ(a["verdict"], "fail");
    const std::string ma = a["message"].get<std::string>();
    EXPECT_NE(ma.find("far.yaml:6: wait-until failed at t=5.600000 s: expected x_m >= 5 within 5.500 s; it was 0."),
              std::string::npos)
        << ma;
    const json b = result_of(dir / "out/fast");
    EXPECT_EQ(b["verdict"], "fail");
    const std::string mb = b["message"].get<std::string>();
    EXPECT_NE(mb.find("fast.yaml:7: expect failed"), std::string::npos) << mb;
    EXPECT_NE(mb.find("expected left.wheel_rad_s in [100, 200], got "), std::string::npos) << mb;
    // Polled at every coupling step (62.5 us): it stops on the first edges past 100.
    const std::string edges = b["steps"][2]["message"].get<std::string>();
    ASSERT_EQ(edges.find("right.edges = "), 0U) << edges;
    const int seen = std::stoi(edges.substr(14));
    EXPECT_GT(seen, 100);
    EXPECT_LE(seen, 102);
}

TEST(ScenarioCommand, ResetRestartsTheFirmwareWithTheRobotAttached) {
    TempDir dir;
    const auto f = write_text(dir, "reset.yaml", R"(name: reset
timeout: 20s
steps:
  - write-serial: "1"
  - wait-serial: "0.6m"
  - delay: 2s
  - expect-var: { name: Count1, type: int32, op: ">", value: 500 }
  - reset:
  - delay: 300ms
  - expect-var: { name: Count1, type: int32, op: "<", value: 100 }   # setup() zeroed it; the wheels coast to a stop
  - expect-pin: { pin: 12, value: 0 }
  - write-serial: "1"
  - wait-serial: "0.6m"
  - delay: 1s
  - expect-var: { name: Count1, type: int32, op: ">", value: 100 }
  - expect-encoders: { max_lost: 0 }
)");
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    const json j = result_of(dir / "out/reset");
    ASSERT_EQ(j["steps"].size(), 13U) << j.dump(1);
    // The second banner comes 5 s (setup()'s delay) after the reset.
    const double t_reset = j["steps"][4]["t_s"].get<double>();
    const double t_banner = j["steps"][9]["t_s"].get<double>();
    EXPECT_GT(t_banner - t_reset, 5.0);
    EXPECT_LT(t_banner - t_reset, 5.1);
    EXPECT_EQ(read_text(dir / "out/reset/uart.txt"), "0.6m\r\n0.6m\r\n");
}

TEST(ScenarioCommand, ASketchIsBuiltOnceAndRun) {
    TempDir dir;
    std::filesystem::create_directories(dir / "suite/copy");
    std::filesystem::copy_file(source_dir() / "firmware/ddmr_tracking/ddmr_tracking.ino", dir / "suite/copy/copy.ino");
    const auto f = write_text(dir, "suite/sketch.yaml", R"(name: sketch
timeout: 8s
firmware: { sketch: copy/copy.ino }
steps:
  - write-serial: "1"
  - wait-serial: "0.6m"
)");
    const std::string env = "XDG_CACHE_HOME=" + sh_quote((dir / "cache").string()) + " ";
    const auto first = run_command(env + sh_quote(cli_path().string()) + " scenario " + sh_quote(f.string()) +
                                   " --out " + sh_quote((dir / "out1").string()));
    EXPECT_EQ(first.exit_code, 0) << first.out << first.err;
    const json j = result_of(dir / "out1/sketch");
    EXPECT_NE(j["firmware"].get<std::string>().find((dir / "cache/ddmr-hil/sketches").string()), std::string::npos);
    // Built as the reference is (same tool, board, flags): the same program.
    const auto built = hil::ElfImage::read(j["firmware"].get<std::string>());
    const auto reference = hil::ElfImage::read(firmware_elf());
    EXPECT_EQ(built.memory_use().flash_bytes(), reference.memory_use().flash_bytes());
    EXPECT_EQ(built.memory_use().ram_bytes(), reference.memory_use().ram_bytes());
    // The same text under another name (a user's copy of an example) is another sketch, not a clash in the cache.
    std::filesystem::create_directories(dir / "suite/other");
    std::filesystem::copy_file(dir / "suite/copy/copy.ino", dir / "suite/other/other.ino");
    const auto o = write_text(dir, "suite/other.yaml", R"(name: other
timeout: 8s
firmware: { sketch: other/other.ino }
steps:
  - write-serial: "1"
  - wait-serial: "0.6m"
)");
    const auto second = run_command(env + sh_quote(cli_path().string()) + " scenario " + sh_quote(o.string()) +
                                    " --out " + sh_quote((dir / "out3").string()));
    EXPECT_EQ(second.exit_code, 0) << second.out << second.err;
    // Broken sketch: refused before anything runs, with the build log named.
    std::filesystem::create_directories(dir / "suite/broken");
    std::ofstream(dir / "suite/broken/broken.ino") << "void setup() { this is not C++ }\nvoid loop() {}\n";
    const auto b = write_text(dir, "suite/broken.yaml", "timeout: 1s\nfirmware: { sketch: broken/broken.ino }\nsteps:\n  - delay: 1ms\n");
    const auto bad = run_command(env + sh_quote(cli_path().string()) + " scenario " + sh_quote(b.string()) + " --out " +
                                 sh_quote((dir / "out2").string()));
    EXPECT_EQ(bad.exit_code, 2);
    EXPECT_NE(bad.err.find("arduino-builder failed"), std::string::npos) << bad.err;
    EXPECT_NE(bad.err.find("failed-broken.log"), std::string::npos) << bad.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out2"));
}

TEST(ScenarioCommand, AnAdapterAtAnotherBaudRateReadsGarbage) {
    TempDir dir;
    const auto f = write_text(dir, "baud.yaml", R"(name: baud
timeout: 8s
serial: { baud: 19200 }
steps:
  - delay: 100ms
  - write-serial: "1"
  - wait-serial: { text: "0.6m", timeout: 6s }
)");
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const json j = result_of(dir / "out/baud");
    EXPECT_EQ(j["verdict"], "fail");
    EXPECT_NE(j["message"].get<std::string>().find("baud.yaml:7: wait-serial failed"), std::string::npos) << j["message"];
    // The firmware's receiver made something of the 19200-baud '1' (it
    // answered with "X"); the adapter read that at the wrong rate.
    EXPECT_GT(j["framing_errors"].get<int>() + static_cast<int>(j["uart_bytes"].get<int>()), 0);
    EXPECT_EQ(read_text(dir / "out/baud/uart.txt").find("X\r\n"), std::string::npos);
    // A failure keeps a VCD window of its last half second.
    const std::string vcd = read_text(dir / "out/baud/failure_window.vcd");
    EXPECT_NE(vcd.find("$timescale 1ns $end"), std::string::npos);
    EXPECT_NE(vcd.find("D1_TX"), std::string::npos);
}

TEST(ScenarioCommand, FailSerialStopsAtTheLine) {
    TempDir dir;
    const auto f = write_text(dir, "unknown.yaml", R"(name: unknown_case
timeout: 8s
steps:
  - fail-serial: "^X$"
  - write-serial: "9"
  - delay: 7s
)");
    const auto junit = dir / "junit.xml";
    const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()) + " --junit " +
                            sh_quote(junit.string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const json j = result_of(dir / "out/unknown_case");
    EXPECT_NE(j["message"].get<std::string>().find("fail-serial '^X$' matched the line 'X'"), std::string::npos)
        << j["message"];
    EXPECT_LT(j["sim_seconds"].get<double>(), 5.2);  // stopped at the line, not after the delay
    const std::string xml = read_text(junit);
    EXPECT_NE(xml.find("failures=\"1\""), std::string::npos) << xml;
    EXPECT_NE(xml.find("<testcase name=\"unknown_case\""), std::string::npos) << xml;
}

// Issue 19, item 5: a wait-serial that runs into the scenario's timeout is
// "the text never came" (a failure, exit 1, with what did come), not a
// firmware error; a step that is not waiting for anything and runs past the
// timeout is the scenario's timeout (exit 3). expect-serial failures show the
// received text's end, escaped.
TEST(ScenarioCommand, AWaitSerialIntoTheTimeoutIsTheTextNeverCame) {
    TempDir dir;
    const auto f = write_text(dir, "slow.yaml", "name: slow\ntimeout: 1s\nsteps:\n  - wait-serial: \"END\"\n");
    auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const std::string m = result_of(dir / "out/slow")["message"].get<std::string>();
    EXPECT_NE(m.find("'END' never came: the scenario's timeout (1 simulated s) came first; received "), std::string::npos)
        << m;
    EXPECT_NE(m.find("ending '"), std::string::npos) << m;
    const auto d = write_text(dir, "long.yaml", "name: long\ntimeout: 1s\nsteps:\n  - delay: 2s\n");
    r = scenario(sh_quote(d.string()) + " --out " + sh_quote((dir / "out2").string()));
    EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
    EXPECT_NE(result_of(dir / "out2/long")["message"].get<std::string>().find("timeout after 1 simulated s"),
              std::string::npos);
    // The sketch prints its banner and waits: expect-serial shows it, \r\n escaped.
    const auto e = write_text(dir, "es.yaml", "name: es\ntimeout: 2s\nsteps:\n  - delay: 1s\n  - expect-serial: \"NOPE\"\n");
    r = scenario(sh_quote(e.string()) + " --out " + sh_quote((dir / "out3").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const std::string em = result_of(dir / "out3/es")["message"].get<std::string>();
    EXPECT_NE(em.find("expected the output to match /NOPE/; it does not: received "), std::string::npos) << em;
    EXPECT_EQ(em.find('\r'), std::string::npos) << em;
}

// Issue 19, item 5: the suite's own outputs. A --junit that cannot be written
// is refused before anything runs; results.json counts the failures; a
// folder an earlier run left for a scenario not in this suite is removed;
// --progress shows each scenario's steps; the first line reads naturally.
TEST(ScenarioCommand, TheSuitesOutputsAreCheckedCountedAndFresh) {
    TempDir dir;
    const auto ok = write_text(dir, "ok.yaml", "name: ok\ntimeout: 1s\nsteps:\n  - delay: 1ms\n");
    const auto bad = write_text(dir, "bad.yaml", "name: bad\ntimeout: 1s\nsteps:\n  - expect-serial: \"NOPE\"\n");
    auto r = scenario(sh_quote(ok.string()) + " --junit " + sh_quote((dir / "nowhere" / "j.xml").string()) + " --out " +
                      sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE(r.err.find("--junit "), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    EXPECT_EQ(r.out.find("PASS"), std::string::npos) << r.out;

    // A JUnit file inside --out: its folder is made by the run (how CI's ctest calls it).
    r = scenario(sh_quote(ok.string()) + " --junit " + sh_quote((dir / "fresh" / "j.xml").string()) + " --out " +
                 sh_quote((dir / "fresh").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "fresh" / "j.xml"));
    std::filesystem::create_directories(dir / "out" / "gone");
    std::ofstream(dir / "out" / "gone" / "result.json") << "{}";
    r = scenario(sh_quote(ok.string()) + " " + sh_quote(bad.string()) + " -j 1 --progress --out " +
                 sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    const json results = json::parse(read_text(dir / "out" / "results.json"));
    EXPECT_EQ(results["passed"], 1);
    EXPECT_EQ(results["failed"], 1);
    EXPECT_EQ(results["errors"], 0);
    EXPECT_FALSE(std::filesystem::exists(dir / "out" / "gone"));
    EXPECT_NE(r.err.find("2 scenarios on 1 worker, results in"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("  start ok ("), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("  [bad] FAIL line 4 expect-serial"), std::string::npos) << r.err;
}

TEST(ScenarioCommand, BadScenariosAreRefusedBeforeAnythingRuns) {
    TempDir dir;
    const auto good = write_text(dir, "good.yaml", "timeout: 1s\nsteps:\n  - delay: 1ms\n");
    const auto bad = write_text(dir, "bad.yaml", "timeout: 1s\nsteps:\n  - delay: 1ms\n  - expect-pin: { pin: 2 }\n");
    const auto r = scenario(sh_quote(good.string()) + " " + sh_quote(bad.string()) + " --out " +
                            sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 2);
    EXPECT_NE(r.err.find("bad.yaml:4: key 'expect-pin': missing required key 'value'"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
    const auto dup = scenario(sh_quote(good.string()) + " " + sh_quote(good.string()) + " --out " +
                              sh_quote((dir / "out").string()));
    EXPECT_EQ(dup.exit_code, 2);
    EXPECT_NE(dup.err.find("is used twice"), std::string::npos) << dup.err;
}

// Issue 19, item 5: a variable the firmware does not have, or one whose size
// needs a type, is bad input found before the run (exit 2, nothing run), not
// a failed check after it (exit 1 reads as a firmware regression in CI).
// Issue 19, item 10: --update-golden records what expect-eeprom and
// expect-pose see (the golden file, the pose values in the scenario file),
// only when every other step passes; the next run passes without it.
TEST(ScenarioCommand, UpdateGoldenRecordsThenTheRunPasses) {
    TempDir dir;
    std::ofstream(dir / "golden.bin") << "old";
    const std::string steps = "timeout: 12s\nsteps:\n  - delay: 100ms\n  - write-serial: \"1\"\n"
                              "  - wait-serial: {text: \"0.6m\", timeout: 6s}\n  - delay: 1s\n"
                              "  - expect-pose: {x_m: 9, y_m: 9, tol_m: 0.0005}\n  - expect-eeprom: {bin: golden.bin}\n";
    const auto f = write_text(dir, "g.yaml", "name: g\n" + steps);
    auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "a").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;  // the made-up values fail
    // A failing step elsewhere: nothing is recorded.
    const auto bad = write_text(dir, "bad.yaml", "name: bad\n" + steps + "  - expect-serial: \"NOPE\"\n");
    const std::string bad_before = read_text(bad);
    r = scenario(sh_quote(bad.string()) + " --update-golden --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    EXPECT_EQ(read_text(bad), bad_before);
    EXPECT_EQ(read_text(dir / "golden.bin"), "old");
    EXPECT_NE(result_of(dir / "b/bad")["message"].get<std::string>().find("nothing recorded, the run did not pass"),
              std::string::npos);
    // Every other step passes: recorded, and the same run now passes without the flag.
    r = scenario(sh_quote(f.string()) + " --update-golden --out " + sh_quote((dir / "c").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_EQ(read_text(dir / "golden.bin").size(), 1024u);
    const std::string yaml = read_text(f);
    EXPECT_EQ(yaml.find("x_m: 9,"), std::string::npos) << yaml;
    EXPECT_NE(yaml.find("tol_m: 0.0005}"), std::string::npos) << yaml;  // the rest of the line as it was
    r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "d").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err << yaml;
}

// Issue 19, item 9: the steps, listed without a scenario file.
TEST(ScenarioCommand, ListStepsPrintsEveryKind) {
    const auto r = scenario("--list-steps");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    for (const char* k : {"  delay: ", "  wait-serial: ", "  expect-no-torn-reads: ", "  reset: "}) {
        EXPECT_NE(r.out.find(k), std::string::npos) << k;
    }
    const auto none = scenario("");
    EXPECT_EQ(none.exit_code, 2);
    EXPECT_NE(none.err.find("give at least one scenario file (or --list-steps)"), std::string::npos) << none.err;
}

TEST(ScenarioCommand, ExpectVarNamesAreCheckedBeforeTheRun) {
    TempDir dir;
    const struct {
        const char* step;
        const char* message;
    } cases[] = {
        {"{name: NoSuchVar, value: 1}", "v.yaml:4: expect-var: the firmware has no symbol 'NoSuchVar'"},
        {"{name: Ex, value: 1}", "v.yaml:4: expect-var: 'Ex' has 4 bytes: give its type"},
        {"{name: Ex, type: int16, value: 1}", "v.yaml:4: expect-var: 'Ex' is 4 bytes; int16 is 2"},
        {"{name: main, value: 1}", "v.yaml:4: expect-var: 'main' is not a variable in SRAM"},
    };
    for (const auto& c : cases) {
        const auto f = write_text(dir, "v.yaml", std::string("name: v\ntimeout: 1s\nsteps:\n  - expect-var: ") + c.step + "\n");
        const auto r = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
        EXPECT_EQ(r.exit_code, 2) << c.step << r.out << r.err;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.step << "\n" << r.err;
        EXPECT_FALSE(std::filesystem::exists(dir / "out")) << c.step;
    }
}

TEST(ScenarioCommand, ExpectNoTornReadsNamesTheTornVariables) {
    // race_fixture (tests/firmware/race_fixture.c): `ticks` read and
    // `setpoint` written without ATOMIC_BLOCK; the fixed build has neither.
    TempDir dir;
    const auto racy = " --firmware " + sh_quote((test_firmware_dir() / "race_fixture_racy.elf").string());
    const auto fixed = " --firmware " + sh_quote((test_firmware_dir() / "race_fixture_fixed.elf").string());
    const auto all = write_text(dir, "all.yaml", "name: all\ntimeout: 1s\nsteps:\n  - delay: 50ms\n  - expect-no-torn-reads\n");
    const auto some = write_text(dir, "some.yaml",
                            "name: some\ntimeout: 1s\nsteps:\n  - delay: 50ms\n  - expect-no-torn-reads: [ticks]\n");
    auto r = scenario(sh_quote(all.string()) + racy + " --out " + sh_quote((dir / "a").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    std::string m = result_of(dir / "a/all")["steps"][1]["message"];
    EXPECT_NE(m.find("read torn of ticks"), std::string::npos) << m;
    EXPECT_NE(m.find("write torn of setpoint"), std::string::npos) << m;
    EXPECT_NE(read_text(dir / "a/all/isr.md").find("### Stale reads"), std::string::npos);
    r = scenario(sh_quote(some.string()) + racy + " --out " + sh_quote((dir / "b").string()));
    EXPECT_EQ(r.exit_code, 1) << r.out << r.err;
    m = result_of(dir / "b/some")["steps"][1]["message"].get<std::string>();
    EXPECT_EQ(m.find("setpoint"), std::string::npos) << m;  // not asked for
    r = scenario(sh_quote(all.string()) + fixed + " --out " + sh_quote((dir / "c").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    // A name that is not a multi-byte variable is refused before the run.
    const auto bad = write_text(dir, "bad.yaml", "name: bad\ntimeout: 1s\nsteps:\n  - expect-no-torn-reads: [flag]\n");
    r = scenario(sh_quote(bad.string()) + racy + " --out " + sh_quote((dir / "d").string()));
    EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
    EXPECT_NE((r.out + r.err).find("bad.yaml:4: expect-no-torn-reads: 'flag' has 1 byte(s)"), std::string::npos)
        << r.out << r.err;
}

TEST(ScenarioCommand, SameScenarioSameBytesAndParallelSameVerdicts) {
    TempDir dir;
    const std::string body = "timeout: 8s\nseed: 3\nsteps:\n  - write-serial: \"1\"\n  - inject: { encoder: 2, drop: 0.2 }\n"
                             "  - wait-serial: \"0.6m\"\n  - delay: 1s\n  - expect-var: { name: Count2, type: int32, op: \">\", value: 0 }\n";
    std::string list;
    for (const char* name : {"a", "b", "c"}) {
        list += " " + sh_quote(write_text(dir, std::string(name) + ".yaml", std::string("name: ") + name + "\n" + body).string());
    }
    const auto serial = scenario(list + " -j 1 --out " + sh_quote((dir / "one").string()));
    const auto parallel = scenario(list + " -j 4 --out " + sh_quote((dir / "four").string()));
    EXPECT_EQ(serial.exit_code, 0) << serial.out << serial.err;
    EXPECT_EQ(parallel.exit_code, 0) << parallel.out << parallel.err;
    for (const char* name : {"a", "b", "c"}) {
        for (const char* file : {"uart.txt", "truth.csv", "eeprom.bin"}) {
            EXPECT_EQ(read_text(dir / "one" / name / file), read_text(dir / "four" / name / file)) << name << file;
        }
    }
    EXPECT_EQ(read_text(dir / "one/results.json"), read_text(dir / "four/results.json"));
    // Same seed, different names: the same robot.
    EXPECT_EQ(read_text(dir / "one/a/truth.csv"), read_text(dir / "one/b/truth.csv"));
}

}  // namespace
}  // namespace ddmr::test

namespace ddmr::test {
namespace {

TEST(ScenarioCommand, ARerunLeavesNoFileOfTheEarlierRun) {
    TempDir dir;
    // Fails first (pin 12 is low before the case byte), leaving its failure window ...
    const auto f = write_text(dir, "again.yaml", "name: again\ntimeout: 1s\nsteps:\n  - delay: 10ms\n"
                                            "  - expect-pin: { pin: 12, value: 1 }\n");
    const auto first = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(first.exit_code, 1) << first.err;
    EXPECT_TRUE(std::filesystem::exists(dir / "out/again/failure_window.vcd"));
    // ... then passes into the same --out: no window of the failure it no longer has.
    write_text(dir, "again.yaml", "name: again\ntimeout: 1s\nsteps:\n  - delay: 10ms\n  - expect-pin: { pin: 12, value: 0 }\n");
    const auto second = scenario(sh_quote(f.string()) + " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(second.exit_code, 0) << second.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out/again/failure_window.vcd"));
}

}  // namespace
}  // namespace ddmr::test
