// HIL speed against bare simavr, measured side by side in one process on the
// same firmware (issue 4's performance goal; issue 8 extends it).
//
//   BareSimavrDefaultLoop : the reference ELF, '1' sent after setup(), PD2/PD3
//                           toggled every 6000 cycles (about the robot's edge
//                           rate), no plant, one avr_run per instruction (how
//                           simavr runs by default: run_cycle_limit = 1)
//   FullHilCase1          : RobotRig defaults: switched PWM, encoders,
//                           datasheet EEPROM timing, ground truth sampled
//   RunCase1              : `ddmr-hil run` (run_firmware): the rig plus the ISR
//                           monitor, race detector, loop tracer and every
//                           artifact written; profiling, VCD and gdb off. Its
//                           ratio to FullHilCase1 is what having those
//                           features costs when they are off (issue 6)
//   RunCase1NoInstruments : `run` with the ISR monitor, stack guard and race
//                           detector off (--no-isr-monitor ...): its ratio to
//                           FullHilCase1 is the engine's own cost (>= 0.95)
//   RunCase1<X>Only       : one of the three on: X's cost is its ratio to
//                           RunCase1NoInstruments
//   RunCase1Profile       : the same with --profile (loop profiler and flat
//                           function profile: single-stepping)
//   RunCase1Vcd           : the same with --vcd
//   ShippedScenarioSuite  : `ddmr-hil scenario tests/scenarios/*.yaml -j 2`,
//                           wall seconds (issue 7's two-minute goal)
//   ScenarioThroughput/J  : 16 case-1 scenarios (16 plant variants) with J
//                           workers: runs per minute; J = 1 and 2 (issue 8)
//   LongRun/M             : one worker process running case 1 again and again
//                           for M simulated minutes (M = 1, 10): Mcycles/s
//                           and the process's peak RSS must not grow with M
//
// Each runs boot + case 1 to the end of its report (~19.6 simulated s); the
// figure is simulated Mcycles per wall second, repeated for a median. The
// program then prints the ratio of the medians and writes them as JSON
// (--ratio_out FILE, default build/bench/hil_ratio.json).
#include <benchmark/benchmark.h>
#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <vector>
#include <fstream>
#include <map>
#include <string>

#include "child_run.hpp"
#include "firmware_run.hpp"
#include "hil/firmware_report.hpp"
#include "hil/robot_rig.hpp"
#include "hil/uart_link.hpp"
#include "support/uno_board.hpp"


namespace {

using ddmr::bench::ChildRun;
using ddmr::bench::run_child;
using ddmr::bench::ScratchDir;
using ddmr::bench::write_text;

using namespace ddmr;
using hil::Cycles;

constexpr double kSimulatedS = 19.6;  // boot (5 s) + 12 s loop + report

struct Toggler {
    hil::AvrCore* core;
    avr_irq_t* pd2;
    avr_irq_t* pd3;
    bool level = false;
};

uint64_t toggle(avr_t* /*avr*/, uint64_t when, void* param) {
    auto* t = static_cast<Toggler*>(param);
    t->level = !t->level;
    avr_raise_irq(t->pd2, t->level ? 1 : 0);
    avr_raise_irq(t->pd3, t->level ? 1 : 0);
    return when + 6000;
}

void BM_BareSimavrDefaultLoop(benchmark::State& state) {
    const auto elf = hil::ElfImage::read(DDMR_BENCH_FIRMWARE_ELF);
    Cycles cycles = 0;
    for (auto _ : state) {
        hil::AvrCoreConfig config;
        config.run_cycle_limit = 1;  // simavr's default: one instruction per avr_run
        hil::AvrCore core(elf, config);
        hil::UartLink uart(core);
        uart.send("1");  // waits in the FIFO until Serial.begin, read after setup()
        avr_t* avr = core.raw();
        Toggler t{&core, avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ('D')), 2),
                  avr_io_getirq(avr, static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ('D')), 3)};
        avr_cycle_timer_register(avr, 6000, &toggle, &t);
        const Cycles end = hil::s_to_cycles(kSimulatedS, ddmr::test::kUnoClockHz);
        while (avr->cycle < end) {
            const int s = avr_run(avr);
            if (s == cpu_Done || s == cpu_Crashed) break;
        }
        cycles += avr->cycle;
    }
    state.counters["Mcycles_per_s"] = benchmark::Counter(static_cast<double>(cycles) / 1e6,
                                                         benchmark::Counter::kIsRate);
}

void BM_FullHilCase1(benchmark::State& state) {
    const auto elf = hil::ElfImage::read(DDMR_BENCH_FIRMWARE_ELF);
    Cycles cycles = 0;
    for (auto _ : state) {
        hil::RobotRig rig(elf, hil::RigConfig{});
        uint64_t rows = 0;
        rig.coupler().set_truth_sink([&](const hil::TruthSample&) { ++rows; });
        hil::FirmwareReportParser parser(true);
        rig.uart().set_listener([&](const hil::UartByte& b) {
            parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
            if (parser.complete()) rig.core().request_stop();
        });
        const Cycles limit = hil::s_to_cycles(40.0, ddmr::test::kUnoClockHz);
        rig.core().run_until_return_from(elf.require("delay"), limit);
        rig.uart().send("1");
        rig.core().run_until(limit);
        if (!parser.complete()) state.SkipWithError("case 1 did not complete");
        benchmark::DoNotOptimize(rows);
        cycles += rig.core().cycle();
    }
    state.counters["Mcycles_per_s"] = benchmark::Counter(static_cast<double>(cycles) / 1e6,
                                                         benchmark::Counter::kIsRate);
}

void run_case1(benchmark::State& state, bool profile, bool vcd, hil::SessionInstruments instruments = {}) {
    Cycles cycles = 0;
    for (auto _ : state) {
        ScratchDir dir;
        tools::FirmwareRunOptions o;
        o.firmware = DDMR_BENCH_FIRMWARE_ELF;
        o.contract = DDMR_DEFAULT_CONTRACT;  // as `ddmr-hil run` does for the reference ELF
        o.out_dir = dir.path / "run";
        o.profile = profile;
        o.instruments = instruments;
        if (vcd) o.vcd = dir.path / "run.vcd";
        const tools::FirmwareRunResult r = tools::run_firmware(o);
        if (r.exit != tools::RunExit::kReportComplete) state.SkipWithError(("case 1 did not complete: " + r.message).c_str());
        cycles += r.cycles_total;
    }
    state.counters["Mcycles_per_s"] = benchmark::Counter(static_cast<double>(cycles) / 1e6,
                                                         benchmark::Counter::kIsRate);
}
void BM_RunCase1(benchmark::State& state) { run_case1(state, false, false); }
void BM_RunCase1Profile(benchmark::State& state) { run_case1(state, true, false); }
void BM_RunCase1Vcd(benchmark::State& state) { run_case1(state, false, true); }
// Each optional instrument on its own, and none (issue 32: each one's cost).
void BM_RunCase1NoInstruments(benchmark::State& state) { run_case1(state, false, false, {false, false, false}); }
void BM_RunCase1IsrMonitorOnly(benchmark::State& state) { run_case1(state, false, false, {true, false, false}); }
void BM_RunCase1StackGuardOnly(benchmark::State& state) { run_case1(state, false, false, {false, true, false}); }
void BM_RunCase1RaceDetectorOnly(benchmark::State& state) { run_case1(state, false, false, {false, false, true}); }

void BM_ShippedScenarioSuite(benchmark::State& state) {
    std::string files;
    for (const auto& e : std::filesystem::directory_iterator(DDMR_BENCH_SCENARIO_DIR)) {
        if (e.path().extension() == ".yaml") files += " '" + e.path().string() + "'";
    }
    for (auto _ : state) {
        ScratchDir dir;
        const std::string cmd = std::string("'") + DDMR_BENCH_CLI + "' scenario" + files + " -j 2 --out '" +
                                (dir.path / "out").string() + "' >/dev/null 2>&1";
        if (std::system(cmd.c_str()) != 0) state.SkipWithError("a shipped scenario failed");
    }
}


void BM_ScenarioThroughput(benchmark::State& state) {
    const auto jobs = state.range(0);
    ScratchDir dir;
    std::vector<std::string> args = {DDMR_BENCH_CLI, "scenario"};
    for (int k = 0; k < 16; ++k) {  // 16 robots: motor 1's resistance from 5.0 to 5.75 ohm
        const auto f = dir.path / ("r" + std::to_string(k) + ".yaml");
        write_text(f, "name: r" + std::to_string(k) + "\ntimeout: 40s\nplant: { overrides: { motor1: { resistance_ohm: " +
                          std::to_string(5.0 + 0.05 * k) + " } } }\nsteps:\n  - write-serial: \"1\"\n" +
                          "  - wait-serial: \"END\"\n");
        args.push_back(f.string());
    }
    args.insert(args.end(), {"-j", std::to_string(jobs), "--out", (dir.path / "out").string()});
    double wall = 0.0;
    for (auto _ : state) {
        const ChildRun r = run_child(args);
        if (r.status != 0) state.SkipWithError("a throughput scenario failed");
        wall += r.wall_s;
    }
    state.counters["runs_per_minute"] = 16.0 * 60.0 / wall * static_cast<double>(state.iterations());
}

void BM_LongRun(benchmark::State& state) {
    const auto minutes = state.range(0);
    ScratchDir dir;
    // Case 1 takes 12.5 s of AVR time from its case byte to the end of its
    // report (after the first, which waits for setup's 5 s): repeat it.
    std::string yaml = "name: long\ntimeout: " + std::to_string(minutes * 60 + 60) + "s\nsteps:\n";
    const int repeats = static_cast<int>(static_cast<double>(minutes * 60) / 14.5) + 1;
    for (int k = 0; k < repeats; ++k) yaml += "  - write-serial: \"1\"\n  - wait-serial: \"END\"\n  - delay: 2s\n";
    const auto f = dir.path / "long.yaml";
    write_text(f, yaml);
    Cycles cycles = 0;
    long rss = 0;
    for (auto _ : state) {
        const auto out = dir.path / "out";
        const ChildRun r = run_child({DDMR_BENCH_CLI, "scenario", "--worker", f.string(), "--out", out.string()});
        if (r.status != 0) state.SkipWithError("the long run failed");
        std::ifstream in(out / "result.json");
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        const auto at = text.find("\"cycles\": ");
        cycles += at == std::string::npos ? 0 : std::stoull(text.substr(at + 10));
        rss = std::max(rss, r.max_rss_kb);
        state.SetIterationTime(r.wall_s);
    }
    state.counters["Mcycles_per_s"] = benchmark::Counter(static_cast<double>(cycles) / 1e6, benchmark::Counter::kIsRate);
    state.counters["peak_rss_MiB"] = static_cast<double>(rss) / 1024.0;
    state.counters["sim_minutes"] = static_cast<double>(minutes);
}

BENCHMARK(BM_BareSimavrDefaultLoop)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_FullHilCase1)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1NoInstruments)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1IsrMonitorOnly)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1StackGuardOnly)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1RaceDetectorOnly)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1Profile)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_RunCase1Vcd)->Iterations(1)->Repetitions(3)->Unit(benchmark::kSecond);
BENCHMARK(BM_ShippedScenarioSuite)->Iterations(1)->Repetitions(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_ScenarioThroughput)->Arg(1)->Arg(2)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK(BM_LongRun)->Arg(1)->Arg(10)->Iterations(1)->Unit(benchmark::kSecond)->UseManualTime();

/// Keeps the median Mcycles/s of each benchmark while printing as usual.
class MedianCollector : public benchmark::ConsoleReporter {
public:
    std::map<std::string, double> medians;
    void ReportRuns(const std::vector<Run>& runs) override {
        for (const Run& r : runs) {
            if (r.run_type == Run::RT_Aggregate && r.aggregate_name == "median") {
                const auto it = r.counters.find("Mcycles_per_s");
                if (it != r.counters.end()) medians[r.run_name.function_name] = it->second.value;
            }
        }
        ConsoleReporter::ReportRuns(runs);
    }
};

}  // namespace

int main(int argc, char** argv) {
    std::string ratio_out = "build/bench/hil_ratio.json";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a.rfind("--ratio_out=", 0) == 0) ratio_out = a.substr(12);
    }
    benchmark::Initialize(&argc, argv);
    MedianCollector reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    benchmark::Shutdown();
    const double bare = reporter.medians["BM_BareSimavrDefaultLoop"];
    const double hil = reporter.medians["BM_FullHilCase1"];
    const double run = reporter.medians["BM_RunCase1"];
    const double prof = reporter.medians["BM_RunCase1Profile"];
    const double vcd = reporter.medians["BM_RunCase1Vcd"];
    if (bare > 0 && hil > 0 && run > 0 && prof > 0 && vcd > 0) {
        std::printf("\nmedian Mcycles/s: bare simavr (default loop) %.1f, full HIL %.1f (%.2fx bare)\n"
                    "  run, features off %.1f (%.3fx the bare rig: their cost when off)\n"
                    "  run --profile %.1f (%.2fx bare, %.1fx real time)\n"
                    "  run --vcd %.1f (%.3fx run)\n",
                    bare, hil, hil / bare, run, run / hil, prof, prof / bare, prof / 16.0, vcd, vcd / run);
        std::ofstream(ratio_out) << "{\n  \"bare_default_loop_mcycles_per_s\": " << bare
                                 << ",\n  \"full_hil_mcycles_per_s\": " << hil
                                 << ",\n  \"ratio_hil_over_bare\": " << hil / bare
                                 << ",\n  \"run_mcycles_per_s\": " << run
                                 << ",\n  \"ratio_run_over_rig\": " << run / hil
                                 << ",\n  \"run_profile_mcycles_per_s\": " << prof
                                 << ",\n  \"profile_real_time_factor\": " << prof / 16.0
                                 << ",\n  \"run_vcd_mcycles_per_s\": " << vcd
                                 << ",\n  \"ratio_vcd_over_run\": " << vcd / run << "\n}\n";
    }
    return 0;
}
