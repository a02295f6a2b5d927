#include "run_command.hpp"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "common/platformio_project.hpp"
#include "common/sketch_build.hpp"
#include "exit_codes.hpp"
#include "firmware_run.hpp"
#include "fast_forward_verify.hpp"
#include "firmware_run_plan.hpp"
#include "hil/board.hpp"
#include "hil/board_description.hpp"
#include "hil/plant_coupler.hpp"

namespace ddmr::tools {

namespace fs = std::filesystem;
namespace {

struct RunCli {
    FirmwareRunOptions options;
    std::string out_dir;
    std::string eeprom_preload;
    std::string uart_timing = "chip";
    std::string plant_file;
    std::string board_file;
    std::string world_file;
    std::string pwm = "switched";
    std::string eeprom_timing = "datasheet";
    std::string vcd;
    bool quiet = false;
    bool progress = false;
    bool no_isr_monitor = false;
    bool no_stack_guard = false;
    bool no_race_detector = false;
    int gdb_port = 0;  ///< 0: no --gdb
    std::vector<std::string> sends;  ///< --send TEXT@TIME
    std::string contract;            ///< --contract FILE
    uint32_t baud = 0;               ///< --baud N (0: none)
    std::string board_name;          ///< --board-name KEY
    std::string sketch;              ///< --sketch x/x.ino: built with arduino-builder
    std::vector<std::string> libraries;  ///< --libraries DIR (repeatable)
    std::string platformio;          ///< --platformio DIR: the project's ELF
    std::string pio_env;             ///< --env NAME
    bool unity = false;              ///< --unity
    bool verify_fast_forward = false;  ///< --verify-fast-forward
    CLI::Option* firmware_option = nullptr;
    CLI::Option* case_option = nullptr;
    CLI::Option* ready_option = nullptr;
    CLI::Option* loop_mark_option = nullptr;
};

}  // namespace

namespace {

/// --sketch or --platformio: builds or finds the ELF (and the board), all
/// checked before anything runs; --libraries and --env only with them.
void resolve_firmware(const RunCli& cli, FirmwareRunOptions& o) {
    const int sources = static_cast<int>(cli.firmware_option->count() > 0) + static_cast<int>(!cli.sketch.empty()) +
                        static_cast<int>(!cli.platformio.empty());
    if (sources > 1) throw std::invalid_argument("give one of --firmware, --sketch and --platformio");
    if (!cli.libraries.empty() && cli.sketch.empty()) {
        throw std::invalid_argument("--libraries: only with --sketch (the sketch to build)");
    }
    if (!cli.pio_env.empty() && cli.platformio.empty()) throw std::invalid_argument("--env: only with --platformio DIR");
    if (!cli.platformio.empty()) {
        // The project folder, or its platformio.ini.
        fs::path dir = cli.platformio;
        if (dir.filename() == "platformio.ini" && fs::is_regular_file(dir)) dir = dir.parent_path();
        const PlatformioProject p = load_platformio_project(dir.empty() ? fs::path(".") : dir, cli.pio_env);
        const std::string env_board = fmt::format("{}'s [env:{}] builds for board = {} ({})",
                                                  (p.dir / "platformio.ini").string(), p.env, p.board_id,
                                                  hil::board_description(p.board).key);
        if (!cli.board_name.empty() && hil::parse_board_key(cli.board_name) != p.board) {
            throw std::invalid_argument(fmt::format("--board-name {}: {}; leave --board-name out, or use the "
                                                    "environment for your board (--env)",
                                                    cli.board_name, env_board));
        }
        o.firmware = p.elf;
        o.board_name = p.board;  // a board file must agree (run_firmware checks it), said as the project's
        o.board_name_origin = env_board;
        o.board_name_advice = fmt::format("; put board: {} in the board file, or use the environment for your board "
                                          "(--env)",
                                          hil::board_description(p.board).key);
        o.firmware_source = platformio_json(p);
    } else if (!cli.sketch.empty()) {
        const fs::path ino = sketch_ino(cli.sketch, "--sketch");
        // The board: --board-name, else the board file's, else the Uno.
        hil::BoardModel model = hil::BoardModel::uno;
        if (!cli.board_name.empty()) {
            if (const auto m = hil::parse_board_key(cli.board_name)) model = *m;
        } else if (!cli.board_file.empty()) {
            model = hil::load_board_file(cli.board_file).model;
        }
        SketchBuildOptions b;
        b.fqbn = hil::board_description(model).fqbn;
        for (const auto& dir : cli.libraries) b.libraries.emplace_back(dir);
        const SketchBuild built = build_sketch(ino, b);
        std::fprintf(stderr, "%s\n", describe_libraries(built).c_str());  // even with -q: what was built from what
        o.firmware = built.elf;
        o.firmware_source = sketch_build_json(built);
    }
    o.unity = cli.unity;
}

/// With --profile: the top-N tables, and where the rest is.
void print_function_profile(const FirmwareRunResult& r, FILE* out) {
    if (r.function_profile_top.empty()) return;
    std::fprintf(out, "%sall functions, source lines and the call graph in profile.txt and profile.json; "
                "callgrind.out for KCachegrind\n",
                r.function_profile_top.c_str());
}

/// With a loop profile: the iterations' compute time and period, those that
/// start an EEPROM write apart.
void print_loop_profile(const FirmwareRunResult& r, FILE* out) {
    if (r.loop_profile.empty()) return;
    // Cycles first (what the firmware costs on any clock), then time.
    // The iterations that start an EEPROM write apart: the write's
    // wait (3.3 ms per byte after the first) is not the control law's.
    const auto cyc_us = [&](double cycles) {
        return fmt::format("{:.0f} cycles ({:.1f} us)", cycles, cycles / r.clock_hz * 1e6);
    };
    std::fprintf(out, "loop profile: %zu iterations measured (all but the first, which has no start):\n",
                r.loop_profile.size());
    for (const bool eeprom : {false, true}) {
        hil::Cycles max_compute = 0, max_period = 0, sum_compute = 0, sum_period = 0;
        std::size_t n = 0;
        for (const auto& it : r.loop_profile) {
            if (it.eeprom_write != eeprom) continue;
            ++n;
            max_compute = std::max(max_compute, it.compute());
            max_period = std::max(max_period, it.period());
            sum_compute += it.compute();
            sum_period += it.period();
        }
        if (n == 0) continue;
        const double dn = static_cast<double>(n);
        std::fprintf(out, "  %4zu %-24s compute mean %s, max %s; period mean %.3f ms, max %.3f ms\n", n,
                    eeprom ? "with an EEPROM write" : "without an EEPROM write",
                    cyc_us(static_cast<double>(sum_compute) / dn).c_str(),
                    cyc_us(static_cast<double>(max_compute)).c_str(),
                    hil::cycles_to_s(sum_period, r.clock_hz) / dn * 1e3,
                    hil::cycles_to_s(max_period, r.clock_hz) * 1e3);
    }
    std::fprintf(out, "  details in loop_profile.csv and summary.json\n");
    if (r.eeprom_writes > r.eeprom_writes_recorded) {
        std::fprintf(out, "loop profile: %llu EEPROM writes, only the first %zu recorded: iterations after "
                    "the last of them are not tagged eeprom_write\n",
                    static_cast<unsigned long long>(r.eeprom_writes), r.eeprom_writes_recorded);
    }
}

/// A run that ended at its time limit (any firmware but one with a complete
/// report): the plant's truth and what the firmware sent.
void print_time_limit(const FirmwareRunOptions& o, const FirmwareRunResult& r, FILE* out) {
    const std::string uart_txt =
        o.baud ? fmt::format("uart.txt: what the adapter at {} baud decoded", *o.baud) : "all in uart.txt";
    std::fprintf(out, "plant truth: end pose (%.4f, %.4f) m, theta %.4f rad; encoder edges %llu / %llu (lost "
                "%llu / %llu); %llu bytes sent on %s (%s)\n",
                r.end_pose_truth.x_m, r.end_pose_truth.y_m, r.end_pose_truth.theta_rad,
                static_cast<unsigned long long>(r.encoder[0].edges_injected),
                static_cast<unsigned long long>(r.encoder[1].edges_injected),
                static_cast<unsigned long long>(r.encoder[0].lost_edges),
                static_cast<unsigned long long>(r.encoder[1].lost_edges),
                static_cast<unsigned long long>(r.uart_bytes), o.serial_port.c_str(), uart_txt.c_str());
    print_function_profile(r, out);
}

/// What `run` prints of a run, and its exit code.
int print_run_result(const FirmwareRunOptions& o, const FirmwareRunResult& r) {
    // With --unity stdout carries the firmware's Unity output only (pio test parses it).
    FILE* out = o.unity ? stderr : stdout;
    const double sim_s = hil::cycles_to_s(r.cycles_total, r.clock_hz);
    std::fprintf(out, "%s: %s after %.3f simulated s (%llu cycles) in %.2f s wall, %.1f Mcycles/s\n",
                o.out_dir.c_str(), to_string(r.exit), sim_s,
                static_cast<unsigned long long>(r.cycles_total), r.wall_seconds,
                r.wall_seconds > 0 ? static_cast<double>(r.cycles_total) / r.wall_seconds / 1e6 : 0.0);
    if (r.exit == RunExit::kTimeLimit) {
        print_time_limit(o, r, out);
        return kExitOk;
    }
    if (r.exit != RunExit::kReportComplete) {
        std::fprintf(stderr, "ddmr-hil run: %s\n", r.message.c_str());
        return kExitFirmware;
    }
    if (r.unity) {
        std::fprintf(stderr, "Unity: %u tests, %u failures, %u ignored: %s\n", r.unity->tests, r.unity->failures,
                     r.unity->ignored, r.unity->ok ? "OK" : "FAIL");
        return r.unity->ok ? kExitOk : kExitCheckFailed;
    }
    const auto& rep = r.report;
    if (r.has_report) {
        // The report's dump has one line more than the log has samples
        // (its last line, j = addr, is a byte the run never wrote).
        std::fprintf(out, "firmware report: Count1 %.0f, Count2 %.0f, end estimate (%.4f, %.4f) m, "
                    "theta %.4f rad, %zu EEPROM log samples\n",
                    rep.count1.value_or(-1), rep.count2.value_or(-1), rep.ex.value_or(0),
                    rep.ey.value_or(0), rep.theta.value_or(0), r.eeprom_log_samples);
    } else if (r.end_pose_firmware) {
        std::fprintf(out, "firmware pose estimate: (%.4f, %.4f) m, theta %.4f rad; %zu EEPROM log samples\n",
                    r.end_pose_firmware->x_m, r.end_pose_firmware->y_m, r.end_pose_firmware->theta_rad,
                    r.eeprom_log_samples);
    }
    std::fprintf(out, "plant truth: end pose (%.4f, %.4f) m, theta %.4f rad; %llu loop iterations, "
                "mean period %.3f ms; lost encoder edges %llu / %llu\n",
                r.end_pose_truth.x_m, r.end_pose_truth.y_m, r.end_pose_truth.theta_rad,
                static_cast<unsigned long long>(r.loop_iterations), r.mean_loop_period_s * 1e3,
                static_cast<unsigned long long>(r.encoder[0].lost_edges),
                static_cast<unsigned long long>(r.encoder[1].lost_edges));
    print_loop_profile(r, out);
    print_function_profile(r, out);
    return kExitOk;
}

/// `run --verify-fast-forward`: the run, its result, and the verification's line.
int run_verified(const FirmwareRunOptions& o) {
    const VerifiedRun v = run_verifying_fast_forward(o);
    const int code = print_run_result(o, v.result);
    const std::string line = verification_line(v.verification, v.result.clock_hz);
    if (v.verification.difference) {
        std::fprintf(stderr, "ddmr-hil run: %s\n", line.c_str());
        return kExitCheckFailed;
    }
    std::fprintf(o.unity ? stderr : stdout, "%s\n", line.c_str());
    return code;
}

/// The run's options from the command line's (`profile_always`: the profile command).
FirmwareRunOptions run_options(const RunCli& cli, bool profile_always) {
    FirmwareRunOptions o = cli.options;
    o.instruments = {!cli.no_isr_monitor, !cli.no_stack_guard, !cli.no_race_detector};
    resolve_firmware(cli, o);
    o.out_dir = cli.out_dir.empty()
                    ? (o.profile && profile_always ? "out/profile-case" : "out/run-case") + std::to_string(o.test_case)
                    : cli.out_dir;
    if (!cli.eeprom_preload.empty()) o.eeprom_preload = cli.eeprom_preload;
    if (cli.baud != 0) o.baud = cli.baud;
    o.case_given = cli.case_option->count() > 0;
    o.ready_symbol_given = cli.ready_option->count() > 0;
    o.reference_protocol_required = o.case_given || o.ready_symbol_given;
    if (!cli.contract.empty()) {
        o.contract = cli.contract;
    } else {
        o.contract = reference_contract_for(o.firmware);  // the reference ELF: its sketch's contract
    }
    o.loop_mark_given = cli.loop_mark_option->count() > 0;
    for (const std::string& spec : cli.sends) o.sends.push_back(parse_send(spec));
    o.uart_timing = cli.uart_timing == "simavr" ? hil::UartTiming::kSimavr : hil::UartTiming::kChip;
    if (!cli.plant_file.empty()) o.plant_file = cli.plant_file;
    if (!cli.board_file.empty()) o.board_file = cli.board_file;
    if (!cli.world_file.empty()) o.world_file = cli.world_file;
    if (!cli.board_name.empty()) o.board_name = hil::parse_board_key(cli.board_name);
    if (!cli.vcd.empty()) o.vcd = cli.vcd;
    o.pwm = cli.pwm == "averaged" ? plant::DriveMode::averaged : plant::DriveMode::switched;
    o.eeprom_timing = cli.eeprom_timing == "instant" ? hil::EepromTimingMode::kInstant
                                                      : hil::EepromTimingMode::kDatasheet;
    o.progress = !cli.quiet && (cli.progress || ::isatty(STDERR_FILENO) != 0);
    if (cli.gdb_port != 0) o.gdb_port = static_cast<uint16_t>(cli.gdb_port);
    return o;
}

/// The firmware to run and how: an ELF, a sketch, a PlatformIO project; Unity; the contract.
void add_firmware_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli) {
    cli->firmware_option = sub->add_option("--firmware", cli->options.firmware,
                    "Firmware ELF for the board's MCU (the ATmega328P on the default Uno)")
        ->capture_default_str();
    sub->add_option("--sketch", cli->sketch,
                    "Build this Arduino sketch (x/x.ino) for the board with arduino-builder (cached) and run it, "
                    "instead of --firmware (docs/firmware.md); a sketch folder x/ means x/x.ino");
    sub->add_option("--libraries", cli->libraries,
                    "A folder of Arduino libraries for --sketch (repeatable; after the sketch's src/, before "
                    "~/Arduino/libraries)")
        ->check(CLI::ExistingDirectory);
    sub->add_option("--platformio", cli->platformio,
                    "Run the ELF `pio run` left in this PlatformIO project (.pio/build/ENV/firmware.elf), on "
                    "the board its platformio.ini names, instead of --firmware");
    sub->add_option("--env", cli->pio_env,
                    "The PlatformIO environment for --platformio [default: default_envs' first, or the only one]");
    sub->add_flag("--unity", cli->unity,
                  "Unity tests (pio test): the UART on stdout as it comes, the run complete when Unity's summary "
                  "(N Tests N Failures N Ignored, then OK or FAIL) has come; exit 0 for OK, 1 for FAIL");
    sub->add_option("--contract", cli->contract,
                    "Sketch contract (YAML, docs/contracts.md): how to start the firmware, when its run is "
                    "complete, its report, pose, loop and EEPROM log; default: the reference sketch's "
                    "(firmware/ddmr_tracking/hil.yaml) for the reference ELF, none for any other firmware")
        ->check(CLI::ExistingFile);
}

/// The run itself: the case, its limits, the output folder, the EEPROM, what the host sends.
void add_run_control_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli) {
    cli->case_option = sub->add_option("--case", cli->options.test_case,
                                       "The contract's {case} in its start text; the reference sketch: 1 = 0.6 m "
                                       "circle in 12 s, 2 = 0.4 m in 8 s")
                           ->capture_default_str();
    sub->add_option("--seconds", cli->options.max_sim_seconds,
                    "Simulated-time limit [s]; the run ends earlier when the report is complete")
        ->capture_default_str();
    sub->add_option("--wall-timeout", cli->options.max_wall_seconds,
                    "Wall-clock limit [s]: the run stops there with exit 3 and its artifacts written (not "
                    "applied while avr-gdb is attached); --seconds limits simulated time")
        ->capture_default_str();
    sub->add_option("--out", cli->out_dir, "Output folder [default: out/run-case<N>]");
    sub->add_option("--eeprom", cli->eeprom_preload,
                    "Preload the EEPROM from this image, the MCU's size (1024 bytes on the ATmega328P, 4096 on the "
                    "ATmega2560; default: erased, all 0xFF)");
    cli->ready_option = sub->add_option("--ready-symbol", cli->options.ready_symbol,
                                        "Reference protocol: send the case byte when the firmware first returns "
                                        "from this function (asks for that protocol)")
                            ->capture_default_str();
    sub->add_option("--baud", cli->baud,
                    "The host's serial adapter at this rate (8N1): it decodes the firmware's frames as a real "
                    "adapter does (garbage and framing errors when the sketch's Serial.begin differs) and sends "
                    "--send text at it; default: the bytes as the firmware sends them")
        ->check(CLI::Range(300U, 2'000'000U));
    sub->add_option("--send", cli->sends,
                    "Send TEXT to the firmware's RX at AVR time TIME: TEXT@TIME, e.g. 'go\\r\\n@2s' (C escapes "
                    "\\r \\n \\t \\\\ \\xHH; TIME in s, ms or us); repeatable")
        ->take_all();
    sub->add_option("--uart-timing", cli->uart_timing,
                    "UART frame time: chip (datasheet, 8N1 = 10 bits) or simavr (1.6's 11 bits)")
        ->check(CLI::IsMember({"chip", "simavr"}))
        ->capture_default_str();
}

/// What is emulated: the plant, the board and its wiring, the serial port, the PWM and EEPROM models, the coupling step.
void add_model_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli) {
    sub->add_option("--plant", cli->plant_file,
                    "Plant parameter YAML (over the embedded defaults)");
    sub->add_option("--board", cli->board_file,
                    "Board file: the board and the robot's wiring (drivers, encoders, pins; docs/boards.md); "
                    "default: the thesis robot on an Uno");
    sub->add_option("--world", cli->world_file,
                    "World file: the floor and its lines, the walls, the robot's start pose (docs/world.md); "
                    "default: an empty floor, the robot at the origin heading +x");
    sub->add_option("--board-name", cli->board_name,
                    "Without --board: the board (its MCU and clock), wired as the thesis robot (right PWM 10 / "
                    "DIR 12 / encoder 2, left 11 / 13 / 3): " + hil::board_key_list() +
                        "; with --board, the file's board: must be this one")
        ->check(CLI::IsMember([] {
            std::vector<std::string> keys;
            for (const hil::BoardModel m : hil::board_models()) keys.emplace_back(hil::board_description(m).key);
            return keys;
        }()));
    sub->add_option("--serial-port", cli->options.serial_port,
                    "The USART the host's serial adapter is on (the contract's start text, --send, the report, "
                    "uart.txt): Serial (USART0, pins 0/1), or Serial1..Serial3 of a Mega 2560 (a Bluetooth "
                    "module on Serial1)")
        ->capture_default_str();
    sub->add_option("--pwm", cli->pwm,
                    "Enable-pin model: switched (the 490 Hz waveform, edge by edge) or averaged (duty)")
        ->check(CLI::IsMember({"switched", "averaged"}))
        ->capture_default_str();
    sub->add_option("--eeprom-timing", cli->eeprom_timing,
                    "EEPROM writes take the datasheet's 3.3 ms (datasheet) or complete at once (instant, "
                    "simavr 1.6)")
        ->check(CLI::IsMember({"datasheet", "instant"}))
        ->capture_default_str();
    sub->add_option("--coupling-step", cli->options.coupling_step_cycles,
                    "Plant step [AVR cycles]: the largest input latency; must divide the 1 ms truth period "
                    "(16000 cycles at 16 MHz) [default: 62.5 us: 1000 cycles at 16 MHz, 500 at 8 MHz]")
        ->check(CLI::Range(hil::Cycles{1}, hil::Cycles{1'000'000}));
}

/// What the run prints while it runs.
void add_console_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli) {
    sub->add_flag("--progress", cli->progress, "Print progress every simulated second (default when "
                                               "stderr is a terminal)");
    sub->add_flag("-q,--quiet", cli->quiet, "No progress output");
    sub->add_flag("-v,--verbose", cli->options.echo_simavr_log, "Echo simavr's warnings to stderr");
    CLI::Option* no_ff = sub->add_flag("!--no-fast-forward", cli->options.fast_forward,
                  "Execute every instruction of busy-wait loops (delay(), flag polls) instead of skipping "
                  "whole passes of them exactly: for comparison (docs/fast-forward.md)");
    sub->add_flag("--verify-fast-forward", cli->verify_fast_forward,
                  "Run the same firmware without fast-forward beside this run, on a second thread, and compare "
                  "their states (cycle, PC, registers, I/O, SRAM, EEPROM, plant) every 10 ms of AVR time; where "
                  "they first differ, repeat both to name the first stop that differs, with the PC and the bytes "
                  "(fast_forward_verify.json; exit 1). Not with --no-fast-forward, --gdb or --unity")
        ->excludes(no_ff);
}

/// The instruments: profiler, variable traces, avr-gdb, VCD, ISR monitor, stack guard, race detector.
void add_instrument_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli, bool profile_always) {
    if (!profile_always) {
        sub->add_flag("--profile", cli->options.profile,
                      "Exact control-loop cycle counts (loop_profile.csv) and a profile: per function, call "
                      "graph and per source line (profile.json, profile.txt), the control loop as "
                      "callgrind.out (KCachegrind); single-steps: several times slower");
    }
    sub->add_option("--trace", cli->options.trace,
                    "Firmware globals to sample into trace.csv, by symbol: NAME or NAME:TYPE (int8 ... uint32, "
                    "float), once per loop iteration")
        ->delimiter(',');
    sub->add_option("--trace-every", cli->options.trace_every_cycles,
                    "With --trace: sample every N AVR cycles instead of once per iteration")
        ->check(CLI::Range(static_cast<hil::Cycles>(1), static_cast<hil::Cycles>(1'000'000'000)));
    sub->add_option("--gdb", cli->gdb_port,
                    "Debug the firmware with avr-gdb (Debian's gdb-avr): listen on 127.0.0.1:PORT (loopback "
                    "only; connections from other hosts are impossible) for one avr-gdb session and wait for it "
                    "before the first instruction, up to 300 s. The plant stays coupled: it stands still while "
                    "gdb holds the CPU. Debugging single-steps simavr, so the run is about 2x slower (case 1: "
                    "~53 instead of ~96 Mcycles/s) until gdb detaches")
        ->option_text("PORT")
        ->check(CLI::Range(1, 65535));
    sub->add_option("--vcd", cli->vcd,
                    "Write a value-change dump (GTKWave) of the run to FILE: the host serial port's RX/TX frames, "
                    "the encoder and motor-driver pins (synthesised PWM, direction), one signal per ISR, the "
                    "loop-iteration count; time in ns of AVR time");
    cli->loop_mark_option =
        sub->add_option("--loop-mark", cli->options.loop_mark,
                        "With --profile: the function each loop iteration calls once (its call ends the compute "
                        "part), by its symbol or C++ name (serialEventRun, MyClass::step); default delay for the "
                        "reference sketch, loop() for any other firmware")
            ->capture_default_str();
    sub->add_flag("--no-isr-monitor", cli->no_isr_monitor,
                  "Leave the ISR monitor off (no isr.json, isr.md; summary.json's isr is null): faster");
    sub->add_flag("--no-stack-guard", cli->no_stack_guard,
                  "Leave the stack guard off (a stack grown into .bss no longer ends the run): faster");
    sub->add_flag("--no-race-detector", cli->no_race_detector,
                  "Leave the race detector off (no torn or stale accesses in isr.json, isr.md): faster");
    sub->add_option("--top", cli->options.profile_top,
                    "With --profile: print the N functions and source lines with the most self cycles "
                    "(profile.json and profile.txt list all)")
        ->check(CLI::Range(std::size_t{1}, std::size_t{100'000}))
        ->capture_default_str();
}

/// The options `run` and `profile` share, and their action.
Subcommand add_run_options(CLI::App* sub, const std::shared_ptr<RunCli>& cli, bool profile_always) {
    cli->options.firmware = DDMR_DEFAULT_FIRMWARE;
    cli->options.profile = profile_always;
    add_firmware_options(sub, cli);
    add_run_control_options(sub, cli);
    add_model_options(sub, cli);
    add_console_options(sub, cli);
    add_instrument_options(sub, cli, profile_always);

    return Subcommand{sub, [cli, profile_always]() {
        const FirmwareRunOptions o = run_options(*cli, profile_always);
        if (cli->verify_fast_forward) return run_verified(o);
        const FirmwareRunResult r = run_firmware(o);
        return print_run_result(o, r);
    }};
}

}  // namespace

Subcommand register_run_command(CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "run",
        "Run the firmware in simavr with the plant and record the UART, the EEPROM, the plant's truth and a "
        "summary. The reference sketch: boot, wait for setup() to end, send the case byte, until its end-of-run "
        "report has been sent. Any other firmware: --seconds of simulated time (exit_reason time_limit).");
    return add_run_options(sub, std::make_shared<RunCli>(), false);
}

Subcommand register_profile_command(CLI::App& app) {
    CLI::App* sub = app.add_subcommand(
        "profile", "`run --profile`: the run, plus exact cycle counts of every control-loop iteration and a "
                   "flat per-function profile (profile.json, profile.txt, the top N on stdout)");
    return add_run_options(sub, std::make_shared<RunCli>(), true);
}

}  // namespace ddmr::tools
