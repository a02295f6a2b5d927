#include "firmware_run.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <functional>
#include <regex>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/firmware_diagnostics.hpp"
#include "common/sha256.hpp"
#include "common/truth_csv.hpp"
#include "callgrind_output.hpp"
#include "exit_codes.hpp"
#include "function_profile_output.hpp"
#include "profile_lines.hpp"
#include "race_report.hpp"
#include "hil/board.hpp"
#include "hil/eeprom_log.hpp"
#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"
#include "hil/function_profiler.hpp"
#include "hil/gdb_server.hpp"
#include "hil/host_adapter.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/loop_tracer.hpp"
#include "hil/race_detector.hpp"
#include "hil/robot_rig.hpp"
#include "hil/run_failure.hpp"
#include "hil/sketch_contract.hpp"
#include "hil/stack_guard.hpp"
#include "hil/vcd_recorder.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>
#include "plant/params_yaml.hpp"

namespace ddmr::tools {
namespace {

using hil::Cycles;
using nlohmann::json;

/// How often progress is reported [simulated s].
constexpr double kProgressPeriodS = 1.0;

json number_or_null(const std::optional<double>& v) {
    if (!v || !std::isfinite(*v)) return nullptr;
    return *v;
}

json report_json(const hil::FirmwareReport& r) {
    json pairs = json::array();
    for (const auto& [x, y] : r.eeprom_pairs) pairs.push_back({x, y});
    return json{
        {"banner", r.banner}, {"ended", r.ended},
        {"count1", number_or_null(r.count1)}, {"count2", number_or_null(r.count2)},
        {"gx", number_or_null(r.gx)}, {"gy", number_or_null(r.gy)}, {"t", number_or_null(r.t)},
        {"pdt1", number_or_null(r.pdt1)}, {"pdt2", number_or_null(r.pdt2)},
        {"v", number_or_null(r.v)}, {"w", number_or_null(r.w)},
        {"ex", number_or_null(r.ex)}, {"ey", number_or_null(r.ey)},
        {"theta", number_or_null(r.theta)},
        {"errx", number_or_null(r.errx)}, {"erry", number_or_null(r.erry)},
        {"errxr", number_or_null(r.errxr)},
        {"addr", number_or_null(r.addr)},
        {"eeprom_pairs", pairs},
    };
}

json stats_json(const hil::CycleDistribution& s, uint32_t clock_hz) {
    const double us = 1e6 / static_cast<double>(clock_hz);
    return json{{"count", s.count},
                {"min_cycles", s.min}, {"mean_cycles", s.mean}, {"p99_cycles", s.p99}, {"max_cycles", s.max},
                {"min_us", static_cast<double>(s.min) * us}, {"mean_us", s.mean * us},
                {"p99_us", static_cast<double>(s.p99) * us}, {"max_us", static_cast<double>(s.max) * us},
                {"histogram", {{"start_cycles", s.bin_start}, {"bin_width_cycles", s.bin_width}, {"counts", s.bins}}}};
}

/// compute / wait / period statistics for all iterations and for those with
/// and without an EEPROM write in their compute part.
json loop_profile_json(const std::vector<hil::LoopIteration>& its, uint32_t clock_hz) {
    json out;
    const auto group = [&](const char* name, auto keep) {
        std::vector<Cycles> compute, wait, period;
        for (const auto& it : its) {
            if (!keep(it)) continue;
            compute.push_back(it.compute());
            wait.push_back(it.wait());
            period.push_back(it.period());
        }
        out[name] = {{"compute", stats_json(hil::cycle_distribution(compute), clock_hz)},
                     {"wait", stats_json(hil::cycle_distribution(wait), clock_hz)},
                     {"period", stats_json(hil::cycle_distribution(period), clock_hz)}};
    };
    group("all", [](const hil::LoopIteration&) { return true; });
    group("without_eeprom_write", [](const hil::LoopIteration& it) { return !it.eeprom_write; });
    group("with_eeprom_write", [](const hil::LoopIteration& it) { return it.eeprom_write; });
    out["iterations"] = its.size();
    return out;
}

std::string loop_profile_table(const std::vector<hil::LoopIteration>& its, uint32_t clock_hz) {
    std::string csv = "iteration,start_cycle,compute_cycles,wait_cycles,period_cycles,compute_us,period_us,eeprom_write\n";
    const double us = 1e6 / static_cast<double>(clock_hz);
    for (std::size_t i = 0; i < its.size(); ++i) {
        const auto& it = its[i];
        fmt::format_to(std::back_inserter(csv), "{},{},{},{},{},{:.4f},{:.4f},{}\n", i + 1, it.start, it.compute(),
                       it.wait(), it.period(), static_cast<double>(it.compute()) * us,
                       static_cast<double>(it.period()) * us, it.eeprom_write ? 1 : 0);
    }
    return csv;
}

json isr_json(const hil::IsrSummary& s) {
    const auto stats = [](const hil::CycleStats& c) {
        return json{{"count", c.count}, {"min_cycles", c.min}, {"mean_cycles", c.mean()}, {"max_cycles", c.max}};
    };
    const auto histogram = [](const hil::CycleHistogram& h) {
        json bins = json::object();
        for (std::size_t b = 0; b < hil::CycleHistogram::kBins; ++b) {
            if (h.counts[b] != 0) bins[hil::CycleHistogram::label(b)] = h.counts[b];
        }
        return bins;
    };
    json vectors = json::array();
    for (const auto& v : s.vectors) {
        vectors.push_back({{"vector", v.vector}, {"name", v.name}, {"handler", v.handler}, {"count", v.count},
                           {"raised", v.raised}, {"reentries", v.reentries},
                           {"latency", stats(v.latency)}, {"duration", stats(v.duration)},
                           {"latency_histogram", histogram(v.latency_histogram)},
                           {"duration_histogram", histogram(v.duration_histogram)},
                           {"cpu_share", v.cpu_share}});
    }
    return json{{"observed_cycles", s.observed_cycles()},
                {"isr_cycles", s.isr_cycles},
                {"interrupts_disabled_cycles",
                 s.interrupts_disabled_cycles ? json(*s.interrupts_disabled_cycles) : json(nullptr)},
                {"max_nesting", s.max_nesting},
                {"vectors", vectors},
                {"raised_not_entered", s.raised_not_entered}};
}

json pose_json(const plant::Pose& p) {
    return json{{"x_m", p.x_m}, {"y_m", p.y_m}, {"theta_rad", p.theta_rad}};
}

/// "name[:type]" -> a traced variable; the type defaults by the symbol's size.
hil::TracedVariable parse_trace_spec(const std::string& spec, const hil::ElfImage& elf) {
    const auto colon = spec.find(':');
    hil::TracedVariable v;
    v.name = spec.substr(0, colon);
    if (v.name.empty()) throw std::invalid_argument("--trace '" + spec + "': empty variable name");
    if (colon != std::string::npos) {
        try {
            v.type = hil::parse_var_type(spec.substr(colon + 1));
        } catch (const std::exception& e) {
            throw std::invalid_argument("--trace '" + spec + "': " + e.what());
        }
        return v;
    }
    const auto sym = elf.find(v.name);
    if (!sym) throw std::invalid_argument("--trace '" + spec + "': firmware has no symbol '" + v.name + "'");
    const auto type = hil::default_var_type(sym->size, hil::FourByteDefault::kFloat);
    if (!type) {
        throw std::invalid_argument("--trace '" + spec + "': '" + v.name + "' has " + std::to_string(sym->size) +
                                    " bytes; give its type as name:type");
    }
    v.type = *type;
    return v;
}

struct PeriodicSampler {
    std::function<void(Cycles)> sample;
    Cycles period = 0;
};

uint64_t on_periodic_sample(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* s = static_cast<PeriodicSampler*>(param);
    s->sample(when);
    return when + s->period;
}

/// Stops the run when the wall clock passes the limit (a cycle timer).
struct WallClockGuard {
    hil::AvrCore* core;
    std::chrono::steady_clock::time_point start;
    double limit_s;
    bool tripped;
    Cycles period;
};

uint64_t on_wall_check(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* g = static_cast<WallClockGuard*>(param);
    if (std::chrono::duration<double>(std::chrono::steady_clock::now() - g->start).count() > g->limit_s) {
        g->tripped = true;
        g->core->request_stop();
        return 0;
    }
    return when + g->period;
}

/// Sees a text go by in a byte stream (a contract's start, pose and
/// completion texts); an empty text is never seen.
class TextWatch {
public:
    explicit TextWatch(std::string text) : text_(std::move(text)) {}
    /// Feeds one byte; true the first time the text is complete.
    bool feed(char c) {
        if (text_.empty() || seen_) return false;
        window_.push_back(c);
        if (window_.size() > text_.size()) window_.erase(window_.begin());
        seen_ = window_ == text_;
        return seen_;
    }
    bool seen() const { return seen_; }

private:
    std::string text_;
    std::string window_;
    bool seen_ = false;
};

/// The loop mark of a firmware without the reference protocol: Arduino's
/// loop() (one call per iteration), or delay() where LTO inlined loop() into main.
std::string default_loop_mark(const hil::ElfImage& elf, const std::string& firmware) {
    const auto loop = elf.find("loop");
    if (loop && loop->is_function && loop->size > 0) return "loop";
    const auto delay = elf.find("delay");
    if (delay && delay->is_function && delay->size > 0) {
        std::fprintf(stderr,
                     "ddmr-hil: loop() is not a function of %s (LTO inlined it into main): the loop mark falls "
                     "back to delay(), one call per iteration (--loop-mark names another)\n",
                     firmware.c_str());
        return "delay";
    }
    throw std::runtime_error(fmt::format("firmware {}: neither loop() nor delay() is a function in the ELF (LTO "
                                         "inlined them): pass --loop-mark FUNCTION, a function each loop "
                                         "iteration calls once",
                                         firmware));
}

RunExit run_exit_of(hil::FailureKind kind) {
    switch (kind) {
        case hil::FailureKind::kStackOverflow: return RunExit::kStackOverflow;
        case hil::FailureKind::kPlantFailed: return RunExit::kPlantFailed;
        case hil::FailureKind::kCrashed: return RunExit::kCrashed;
        case hil::FailureKind::kSleepForever: return RunExit::kSleepForever;
        case hil::FailureKind::kWatchdogReset: return RunExit::kWatchdogReset;
        case hil::FailureKind::kSimavrError: return RunExit::kSimavrError;
        case hil::FailureKind::kResetLoop: return RunExit::kResetLoop;
    }
    return RunExit::kCrashed;
}

hil::RigConfig rig_config(const FirmwareRunOptions& o) {
    hil::RigConfig c;
    if (o.plant_file) {
        c.plant = plant::load_robot_params(*o.plant_file);
    }
    if (o.board_file) {
        c.board = hil::load_board_file(*o.board_file);
        if (o.board_name && *o.board_name != c.board.model) {
            const std::string origin = o.board_name_origin.empty()
                                           ? fmt::format("--board-name {}", hil::board_description(*o.board_name).key)
                                           : o.board_name_origin;
            throw std::invalid_argument(fmt::format("{}: the board file {} is for the {} (board: {}){}", origin,
                                                    c.board.source, hil::board_description(c.board.model).label,
                                                    hil::board_description(c.board.model).key, o.board_name_advice));
        }
    } else if (o.board_name) {
        c.board.model = *o.board_name;  // the thesis robot's wiring on that board
        c.board.source = fmt::format("built-in default board on the {}", hil::board_description(*o.board_name).key);
        hil::validate(c.board);
    }
    c.coupler.mode = o.pwm;
    c.coupler.step_cycles = o.coupling_step_cycles;
    // PlantCoupler checks this too; here the message names the option and the board.
    const hil::BoardDescription& board = hil::board_description(c.board.model);
    const hil::CouplerConfig coupler = hil::resolved(c.coupler, board.clock_hz);
    if (coupler.truth_period_cycles % coupler.step_cycles != 0) {
        throw std::invalid_argument(fmt::format("--coupling-step {} cycles: must divide the {}-cycle (1 ms) truth "
                                                "period of the {} at {} MHz",
                                                coupler.step_cycles, coupler.truth_period_cycles, board.label,
                                                board.clock_hz / 1e6));
    }
    c.eeprom_timing = o.eeprom_timing;
    c.uart_timing = o.uart_timing;
    const std::optional<int> port = hil::parse_serial_port(board, o.serial_port);
    if (!port) {
        throw std::invalid_argument(fmt::format("--serial-port {}: the {} ({}) has {}", o.serial_port, board.label,
                                                board.mcu->label, hil::serial_port_list(board)));
    }
    c.host_usart = *port;
    return c;
}

}  // namespace

const char* to_string(RunExit exit) {
    switch (exit) {
        case RunExit::kReportComplete: return "report_complete";
        case RunExit::kTimeout: return "timeout";
        case RunExit::kCrashed: return "crashed";
        case RunExit::kSleepForever: return "sleep_with_interrupts_off";
        case RunExit::kReportMalformed: return "report_malformed";
        case RunExit::kPlantFailed: return "plant_failed";
        case RunExit::kKilledByDebugger: return "killed_by_debugger";
        case RunExit::kWallTimeout: return "wall_timeout";
        case RunExit::kWatchdogReset: return "watchdog_reset";
        case RunExit::kSimavrError: return "simavr_error";
        case RunExit::kStackOverflow: return "stack_overflow";
        case RunExit::kTimeLimit: return "time_limit";
        case RunExit::kResetLoop: return "reset_loop";
    }
    return "unknown";
}

FirmwareRunOptions::Send parse_send(const std::string& spec) {
    const auto at = spec.rfind('@');
    if (at == std::string::npos) throw std::invalid_argument("--send '" + spec + "': expected TEXT@TIME, e.g. 1@2s");
    const std::string text = spec.substr(0, at);
    const std::string time = spec.substr(at + 1);
    FirmwareRunOptions::Send s;
    for (std::size_t i = 0; i < text.size(); ++i) {
        if (text[i] != '\\' || i + 1 == text.size()) {
            s.bytes.push_back(text[i]);
            continue;
        }
        const char e = text[++i];
        if (e == 'r') {
            s.bytes.push_back('\r');
        } else if (e == 'n') {
            s.bytes.push_back('\n');
        } else if (e == 't') {
            s.bytes.push_back('\t');
        } else if (e == '\\') {
            s.bytes.push_back('\\');
        } else if (e == 'x' && i + 2 < text.size() && std::isxdigit(static_cast<unsigned char>(text[i + 1])) != 0 &&
                   std::isxdigit(static_cast<unsigned char>(text[i + 2])) != 0) {
            s.bytes.push_back(static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16)));
            i += 2;
        } else {
            throw std::invalid_argument(
                fmt::format("--send '{}': unknown escape '\\{}' (known: \\r \\n \\t \\\\ \\xHH)", spec, e));
        }
    }
    if (s.bytes.empty()) throw std::invalid_argument("--send '" + spec + "': nothing to send");
    double value = -1.0;
    std::size_t used = 0;
    try {
        value = std::stod(time, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    const std::string unit = time.substr(used);
    const double scale = unit == "s" ? 1.0 : unit == "ms" ? 1e-3 : unit == "us" ? 1e-6 : -1.0;
    if (used == 0 || scale < 0 || !(value >= 0.0) || !std::isfinite(value)) {
        throw std::invalid_argument("--send '" + spec + "': TIME '" + time +
                                    "' must be a non-negative number with a unit: s, ms or us (e.g. 2s)");
    }
    s.at_s = value * scale;
    return s;
}

FirmwareRunResult run_firmware(const FirmwareRunOptions& options) {
    // --- Validate everything before the output folder is touched. ---
    std::optional<hil::SketchContract> contract;
    if (options.contract) contract = hil::load_sketch_contract(*options.contract);
    if (!contract && options.reference_protocol_required) {
        throw std::invalid_argument(fmt::format(
            "--case / --ready-symbol need a sketch contract (run --contract FILE, docs/contracts.md): {} has none",
            options.firmware.string()));
    }
    const bool has_start = contract && contract->start;
    if (options.case_given && !(has_start && !contract->start->cases.empty())) {
        throw std::invalid_argument(fmt::format("--case {}: the sketch contract {} takes no case", options.test_case,
                                                contract ? contract->source : std::string("(none)")));
    }
    const int test_case = has_start && !contract->start->cases.empty()
                              ? (options.case_given ? options.test_case : contract->start->default_case)
                              : 0;
    const std::string start_text = has_start ? contract->start_text(test_case) : std::string();
    if (!(options.max_wall_seconds > 0.0) || !std::isfinite(options.max_wall_seconds)) {
        throw std::invalid_argument(fmt::format("--wall-timeout {}: must be a positive number of seconds",
                                                options.max_wall_seconds));
    }
    if (!(options.max_sim_seconds > 0.0) || !std::isfinite(options.max_sim_seconds)) {
        throw std::invalid_argument(
            fmt::format("--seconds {}: must be a positive number of simulated seconds",
                        options.max_sim_seconds));
    }
    if (options.vcd) {
        try {
            check_output_file(*options.vcd);
        } catch (const std::exception& e) {
            throw std::invalid_argument("--vcd " + options.vcd->string() + ": " + e.what());
        }
    }
    const hil::ElfImage elf = hil::ElfImage::read(options.firmware);
    const hil::RigConfig config = rig_config(options);  // the board file's errors first
    const hil::BoardDescription& board = hil::board_description(config.board.model);
    elf.require_mcu(*board.mcu, board.key);
    hil::AvrCore::check_loadable(elf, *board.mcu);
    // Calls to address 0: a sketch built here was reported by its build.
    const hil::ZeroCallReport zero_calls = scan_zero_calls(elf, !options.firmware_source.contains("sketch"));
    // What the contract names must be in the ELF (checked before anything is written).
    std::optional<hil::ElfSymbol> ready;
    std::string ready_symbol;
    if (has_start && (contract->start->after_return || options.ready_symbol_given)) {
        ready_symbol = options.ready_symbol_given ? options.ready_symbol : *contract->start->after_return;
        ready = elf.find(ready_symbol);
        if (!ready || !ready->is_function) {
            throw std::runtime_error(fmt::format("firmware {}: has no function '{}' ({})", options.firmware.string(),
                                                 ready_symbol,
                                                 options.ready_symbol_given ? "--ready-symbol"
                                                                            : "the contract's start.after-return"));
        }
    }
    std::vector<hil::TracedVariable> traced;
    std::optional<hil::TracedVariable> loop_marker;
    if (contract && contract->loop.marker) {
        loop_marker = parse_trace_spec(*contract->loop.marker, elf);
        for (const auto& spec : contract->trace) traced.push_back(parse_trace_spec(spec, elf));
        if (std::none_of(traced.begin(), traced.end(), [&](const auto& v) { return v.name == loop_marker->name; })) {
            traced.push_back(*loop_marker);
        }
    }
    if (contract && contract->pose) {
        for (const std::string& name : {contract->pose->x, contract->pose->y, contract->pose->theta}) {
            const auto sym = elf.find(name);
            if (!sym || !sym->is_object || sym->size != 4) {
                throw std::runtime_error(fmt::format("firmware {}: has no 4-byte float global '{}' (the contract {}'s pose)",
                                                     options.firmware.string(), name, contract->source));
            }
        }
    }
    if (contract && contract->eeprom_log) {
        const auto& l = *contract->eeprom_log;
        if (l.max_samples(static_cast<int>(board.mcu->eeprom_bytes)) == 0) {
            throw std::invalid_argument(fmt::format(
                "contract {}: eeprom-log: the series at x-address {} and y-address {} leave no room for a sample "
                "in the {}'s {}-byte EEPROM",
                contract->source, l.x_address, l.y_address, board.mcu->label, board.mcu->eeprom_bytes));
        }
    }
    const bool reports = contract && contract->report == hil::ReportFormat::kDdmrTracking;
    // --unity replaces the contract's `complete` (Unity's summary ends the run).
    const bool contract_completes = !options.unity && contract && contract->complete;
    const bool completes = options.unity || contract_completes;
    std::optional<hil::ElfSymbol> loop_mark;
    if (options.profile_top == 0) {
        throw std::invalid_argument("--top 0: give the number of functions to print, >= 1");
    }
    const std::string loop_mark_name =
        options.loop_mark_given || !options.profile ? options.loop_mark
        : contract && contract->loop.function       ? *contract->loop.function
                                                    : default_loop_mark(elf, options.firmware.string());
    if (options.profile) {
        loop_mark = elf.require(loop_mark_name);
        if (!loop_mark->is_function || loop_mark->size == 0) {
            throw std::runtime_error(fmt::format("firmware {}: --loop-mark '{}' is not a function",
                                                 options.firmware.string(), loop_mark_name));
        }
    }
    std::vector<FirmwareRunOptions::Send> sends = options.sends;
    std::stable_sort(sends.begin(), sends.end(), [](const auto& a, const auto& b) { return a.at_s < b.at_s; });
    std::optional<hil::EepromImage> preload;
    if (options.eeprom_preload) preload = hil::EepromPort::load_image(*options.eeprom_preload, *board.mcu);
    const std::string sha256 = sha256_file_hex(options.firmware);

    auto wall_start = std::chrono::steady_clock::now();
    hil::RobotRig rig(elf, config);
    hil::AvrCore& core = rig.core();
    hil::UartLink& uart = rig.uart();
    core.log().set_echo(options.echo_simavr_log ? stderr : nullptr);
    if (preload) rig.eeprom().preload(*preload);
    // The contract's globals traced per iteration (firmware.csv), validated
    // here, before anything is written.
    std::optional<hil::LoopTracer> tracer;
    if (loop_marker) tracer.emplace(rig.variables(), *loop_marker, traced);
    hil::IsrMonitor isr_monitor(core, elf);
    const hil::StackGuard stack_guard(core, elf);
    // Races on every ISR-shared variable (torn reads and writes, stale reads).
    hil::RaceDetector races(core, elf);
    std::optional<hil::LoopProfiler> profiler;
    // The function profile's control-loop scope uses the loop profiler's
    // iterations; built before the first instruction, it sees the whole stack.
    std::optional<hil::FunctionProfiler> function_profiler;
    if (loop_mark) {
        profiler.emplace(core, *loop_mark);
        function_profiler.emplace(core);
        // The compute scope: the loop without the wait in its mark (delay() and what it calls).
        function_profiler->set_wait_function(function_profiler->map().at(loop_mark->address));
        profiler->set_iteration_listener([&](bool completed) { function_profiler->on_loop_boundary(completed); });
    }
    // trace.csv: the user's globals, per iteration or every N cycles.
    std::vector<hil::TracedVariable> trace_vars;
    for (const auto& spec : options.trace) trace_vars.push_back(parse_trace_spec(spec, elf));
    std::optional<hil::LoopTracer> trace_tracer;
    std::vector<hil::Variable> trace_handles;
    if (!trace_vars.empty() && options.trace_every_cycles == 0 && !loop_marker) {
        throw std::invalid_argument("--trace without --trace-every samples once per loop iteration, which needs "
                                    "the sketch contract's loop.marker: give --trace-every N (cycles)");
    }
    if (!trace_vars.empty()) {
        // validates every name and size (the marker only matters per iteration)
        trace_tracer.emplace(rig.variables(), loop_marker.value_or(trace_vars.front()), trace_vars);
        for (const auto& v : trace_vars) trace_handles.push_back(rig.variables().lookup(v.name, v.type));
    }
    // The gdb port is bound here, so a port in use is refused before anything
    // is written; the run then waits for avr-gdb before its first instruction.
    std::optional<hil::GdbServer> gdb;
    if (options.gdb_port) {
        gdb.emplace(core, hil::GdbServerConfig{*options.gdb_port, options.gdb_attach_timeout_s});
        std::fprintf(stderr,
                     "ddmr-hil: waiting for avr-gdb on 127.0.0.1:%u (loopback only): "
                     "avr-gdb -ex 'target remote 127.0.0.1:%u' %s\n",
                     unsigned{*options.gdb_port}, unsigned{*options.gdb_port}, options.firmware.c_str());
        gdb->wait_for_attach();
        wall_start = std::chrono::steady_clock::now();  // the wait for a person is not run time
    }
    const auto killed = [&gdb] { return gdb && gdb->killed(); };
    prepare_output_dir(options.out_dir);
    // --vcd: a recorder on the rig, streaming to the atomic file.
    std::optional<AtomicFileWriter> vcd_file;
    std::optional<hil::VcdWriter> vcd_writer;
    std::optional<hil::VcdRecorder> vcd;
    if (options.vcd) {
        vcd_file.emplace(*options.vcd);
        hil::VcdConfig vcd_config;
        vcd_config.clock_hz = core.clock_hz();
        vcd_writer.emplace([&file = *vcd_file](std::string_view text) { file.write(text); }, vcd_config);
        vcd.emplace(rig, elf, *vcd_writer, profiler ? &*profiler : nullptr);
    }
    if (!completes) {
        std::fprintf(stderr,
                     "ddmr-hil: %s: %s, so it runs %g simulated s (--seconds) and ends with exit_reason time_limit\n",
                     options.firmware.c_str(),
                     contract ? "the sketch contract says nothing about when a run is complete"
                              : "no sketch contract (--contract FILE, docs/contracts.md)",
                     options.max_sim_seconds);
    }

    // --- Streamed outputs (atomic: renamed into place at the end). ---
    AtomicFileWriter truth_csv(options.out_dir / "truth.csv");
    truth_csv.write(truth_csv_header(/*with_drive=*/true));
    std::string row;
    rig.coupler().set_truth_sink([&](const hil::TruthSample& s) {
        row.clear();
        append_truth_row(row, s, /*with_drive=*/true);
        truth_csv.write(row);
    });
    std::optional<AtomicFileWriter> firmware_csv;
    // uart.txt grows as the firmware writes, so no copy of it is held in memory.
    AtomicFileWriter uart_txt(options.out_dir / "uart.txt");
    if (tracer) {
        firmware_csv.emplace(options.out_dir / "firmware.csv");
        std::string header = "iteration,cycle,t_avr_s";
        for (const auto& v : traced) header += "," + v.name;
        firmware_csv->write(header + "\n");
    }
    // Loop period: gaps between consecutive iterations whose `t` increased
    // (the sketch resets t to 0 after its report: not an iteration).
    double last_t = 0.0;
    Cycles last_iteration_cycle = 0;
    bool have_last = false;
    Cycles period_sum = 0;
    uint64_t period_count = 0;
    uint64_t loop_iterations = 0;
    const auto t_index = static_cast<std::size_t>(
        std::find_if(traced.begin(), traced.end(), [&](const auto& v) { return v.name == loop_marker->name; }) -
        traced.begin());
    // A control-loop iteration is an increase of the marker: one definition
    // for loop_iterations, firmware.csv's rows (its `iteration` column counts
    // them from 1) and the loop period. A change that is not an increase
    // (the reference sketch zeroes t after its report) is no iteration and
    // has no row.
    if (tracer) tracer->set_sink([&](Cycles cycle, const std::vector<double>& values) {
        const double t = values[t_index];
        if (t > last_t) {
            ++loop_iterations;
            row.clear();
            fmt::format_to(std::back_inserter(row), "{},{},{:.7f}", loop_iterations, cycle,
                           hil::cycles_to_s(cycle, core.clock_hz()));
            for (double v : values) fmt::format_to(std::back_inserter(row), ",{:.9g}", v);
            row.push_back('\n');
            firmware_csv->write(row);
            if (vcd) vcd->mark_loop_iteration(cycle);
            if (have_last) {
                period_sum += cycle - last_iteration_cycle;
                ++period_count;
            }
            have_last = true;
            last_iteration_cycle = cycle;
        } else {
            have_last = false;
        }
        last_t = t;
    });
    std::optional<AtomicFileWriter> trace_csv;
    PeriodicSampler periodic;
    uint64_t trace_rows = 0;
    if (trace_tracer) {
        trace_csv.emplace(options.out_dir / "trace.csv");
        std::string header = options.trace_every_cycles > 0 ? "row,cycle,t_avr_s" : "iteration,cycle,t_avr_s";
        for (const auto& v : trace_vars) header += "," + v.name;
        trace_csv->write(header + "\n");
        const auto write_row = [&](Cycles cycle, const std::vector<double>& values) {
            std::string r = fmt::format("{},{},{:.7f}", ++trace_rows, cycle, hil::cycles_to_s(cycle, core.clock_hz()));
            for (double v : values) fmt::format_to(std::back_inserter(r), ",{:.9g}", v);
            r.push_back('\n');
            trace_csv->write(r);
        };
        if (options.trace_every_cycles > 0) {
            periodic.period = options.trace_every_cycles;
            periodic.sample = [&, write_row](Cycles cycle) {
                std::vector<double> values;
                values.reserve(trace_handles.size());
                for (const auto& h : trace_handles) values.push_back(rig.variables().read(h));
                write_row(cycle, values);
            };
            avr_cycle_timer_register(core.raw(), options.trace_every_cycles, &on_periodic_sample, &periodic);
        } else {
            trace_tracer->set_sink(write_row);
        }
    }
    std::optional<hil::HostAdapter> adapter;
    if (options.baud) adapter.emplace(core, rig.uart().usart(), *options.baud);
    std::vector<hil::LineByte> settled;

    FirmwareRunResult result;
    // The ddmr-tracking report's EEPROM dump follows only case 1's report.
    hil::FirmwareReportParser parser(/*expects_eeprom_dump=*/test_case == 1);
    // The firmware's pose estimate, read as the contract's text arrives (the
    // reference sketch reuses Ex/Ey right after "END") or at the end.
    std::optional<hil::Variable> pose_x, pose_y, pose_theta;
    if (contract && contract->pose) {
        pose_x = rig.variables().lookup(contract->pose->x, hil::VarType::kFloat);
        pose_y = rig.variables().lookup(contract->pose->y, hil::VarType::kFloat);
        pose_theta = rig.variables().lookup(contract->pose->theta, hil::VarType::kFloat);
    }
    const auto read_pose = [&] {
        const auto& vars = rig.variables();
        result.end_pose_firmware = plant::Pose{vars.read(*pose_x), vars.read(*pose_y), vars.read(*pose_theta)};
    };
    // Texts the contract waits for in what the firmware sends.
    TextWatch start_watch(has_start && contract->start->after_text ? *contract->start->after_text : "");
    TextWatch pose_watch(pose_x && contract->pose->at_text ? *contract->pose->at_text : "");
    TextWatch done_watch(contract_completes && contract->complete->text ? *contract->complete->text : "");
    UnitySummaryWatch unity_watch;
    // lines-after: the end of the text's own line, then that many more lines.
    int lines_to_go = 0;
    if (contract_completes && contract->complete->text) {
        lines_to_go = contract->complete->lines_after + (contract->complete->text->back() == '\n' ? 0 : 1);
    }
    bool done = false;
    bool start_seen = false;
    bool started = !has_start;  // the start text has been sent
    // What the host receives: the firmware's bytes as sent, or (--baud) as the
    // host's adapter at its own rate decodes them.
    // Report fields (the contract's report: {fields}): each line is matched
    // against every pattern; the last match of each gives its value.
    std::vector<std::regex> field_patterns;
    if (contract) {
        for (const auto& f : contract->report_fields) field_patterns.emplace_back(f.pattern);
    }
    std::vector<std::optional<double>> field_values(field_patterns.size());
    std::string field_line;
    const auto match_fields = [&] {
        for (std::size_t i = 0; i < field_patterns.size(); ++i) {
            std::smatch m;
            if (!std::regex_search(field_line, m, field_patterns[i]) || m.size() < 2) continue;
            const std::string text = m[1].str();
            char* end = nullptr;
            const double v = std::strtod(text.c_str(), &end);
            field_values[i] = (end != text.c_str()) ? std::optional<double>(v) : std::nullopt;
        }
        field_line.clear();
    };
    constexpr std::size_t kMaxFieldLine = 4096;  // a longer line is cut (bounded memory on a flood)
    const auto on_host_byte = [&](const char c) {
        uart_txt.write(std::string_view(&c, 1));
        if (!field_patterns.empty()) {
            if (c == '\n') {
                match_fields();
            } else if (c != '\r' && field_line.size() < kMaxFieldLine) {
                field_line.push_back(c);
            }
        }
        if (start_watch.feed(c)) {
            start_seen = true;
            if (!started) core.request_stop();  // the run loop sends the start text now
        }
        if (pose_watch.feed(c) && !result.end_pose_firmware) read_pose();
        if (options.unity) {
            std::fputc(c, stdout);  // pio test reads Unity's lines from stdout as they come
            if (c == '\n') std::fflush(stdout);
            if (!done && unity_watch.feed(c)) {
                done = true;
                result.unity = unity_watch.summary();
                core.stop_after(uart.cycles_per_byte());  // the last byte has left the wire
            }
        }
        if (contract_completes && contract->complete->text && !done) {
            if (done_watch.seen()) {
                if (c == '\n') --lines_to_go;
            } else {
                done_watch.feed(c);
            }
            if (done_watch.seen() && lines_to_go <= 0) {
                done = true;
                core.stop_after(uart.cycles_per_byte());  // the last byte has left the wire
            }
        }
        if (!reports) return;
        const bool was_done = parser.complete() || parser.error().has_value();
        parser.feed(std::string_view(&c, 1));
        if (was_done) return;
        if (parser.error()) {
            core.request_stop();
        } else if (parser.complete() && contract_completes && contract->complete->report) {
            done = true;
            core.stop_after(uart.cycles_per_byte());  // the last byte has left the wire
        }
    };
    rig.coupler().set_boundary_hook([&](Cycles cycle) {
        if (adapter) {
            settled.clear();
            adapter->settle(cycle, settled);  // bytes whose stop bit the adapter has sampled
            for (const auto& d : settled) on_host_byte(static_cast<char>(d.value));
        }
        if (tracer) tracer->poll(cycle);
        if (trace_tracer && options.trace_every_cycles == 0) trace_tracer->poll(cycle);
        if (vcd) vcd->on_boundary(cycle);
    });
    std::vector<hil::LineByte> decoded;
    uart.set_listener([&](const hil::UartByte& b) {
        if (!adapter) {
            on_host_byte(static_cast<char>(b.value));
            return;
        }
        decoded.clear();
        adapter->on_firmware_byte(b, decoded);
        for (const auto& d : decoded) on_host_byte(static_cast<char>(d.value));
    });
    const auto host_sends = [&](const std::string& text) {
        uart.send(adapter ? adapter->as_firmware_receives(text) : text);
    };

    const Cycles limit = hil::s_to_cycles(options.max_sim_seconds, core.clock_hz());
    const auto progress = [&](const char* phase) {
        if (!options.progress) return;
        std::fprintf(stderr, "ddmr-hil run: %-8s t = %6.2f s of %.0f s simulated, %llu UART bytes\n",
                     phase, core.seconds(), options.max_sim_seconds,
                     static_cast<unsigned long long>(uart.bytes_received()));
    };

    // The wall-clock limit: checked every simulated second by a cycle timer,
    // so it also ends a boot that never returns from the ready symbol.
    WallClockGuard wall_guard{&core, wall_start, options.max_wall_seconds, false,
                              hil::s_to_cycles(kProgressPeriodS, core.clock_hz())};
    if (!options.gdb_port) avr_cycle_timer_register(core.raw(), wall_guard.period, &on_wall_check, &wall_guard);
    // --send bytes go out at their times (those due during the reference
    // sketch's boot at its ready point, with the case byte).
    std::size_t next_send = 0;
    const auto send_cycle = [&](std::size_t i) { return hil::s_to_cycles(sends[i].at_s, core.clock_hz()); };
    const auto send_due = [&] {
        for (; next_send < sends.size() && send_cycle(next_send) <= core.cycle(); ++next_send) {
            host_sends(sends[next_send].bytes);
        }
    };
    hil::RunStop stop = hil::RunStop::kReachedCycle;
    // The contract's start text: once the firmware returns from its ready
    // function (run up to that first), at an AVR time, or after a text.
    const auto send_start = [&] {
        result.ready_cycle = core.cycle();
        progress("ready");
        if (profiler) profiler->arm();
        host_sends(start_text);
        started = true;
    };
    if (ready) {
        stop = killed() ? hil::RunStop::kCondition : core.run_until_return_from(*ready, limit);
        if (gdb) gdb->release_if_detached();
    } else if (profiler && !has_start) {
        profiler->arm();  // every iteration from reset on
    }
    const bool booted = !ready || (stop == hil::RunStop::kCondition && !killed() && !wall_guard.tripped &&
                                   rig.coupler().status() == plant::StepStatus::ok);
    if (booted) {
        if (ready) send_start();
        std::optional<Cycles> start_at;
        if (has_start && contract->start->at_s) start_at = hil::s_to_cycles(*contract->start->at_s, core.clock_hz());
        const Cycles progress_period = hil::s_to_cycles(kProgressPeriodS, core.clock_hz());
        Cycles next_progress = core.cycle() + progress_period;
        stop = hil::RunStop::kReachedCycle;
        while (core.cycle() < limit && !killed()) {
            if (stop == hil::RunStop::kCondition) {
                // Only the start text stops the run and goes on: it is sent now.
                if (started || !start_seen || parser.error() || done) break;
                core.clear_stop_request();
                send_start();
            } else if (stop != hil::RunStop::kReachedCycle) {
                break;
            }
            send_due();
            if (!started && start_at && core.cycle() >= *start_at) send_start();
            Cycles next = std::min(limit, next_progress);
            if (next_send < sends.size()) next = std::min(next, send_cycle(next_send));
            if (!started && start_at) next = std::min(next, *start_at);
            stop = core.run_until(next);
            if (gdb) gdb->release_if_detached();  // back to full speed once gdb has left
            if (stop == hil::RunStop::kReachedCycle && core.cycle() >= next_progress) {
                progress("running");
                next_progress = core.cycle() + progress_period;
            }
        }
    }
    if (pose_x && !result.end_pose_firmware) read_pose();  // no text to read it at: the pose at the end

    if (adapter) {  // bytes still on the wire reach the adapter
        settled.clear();
        adapter->flush(settled);
        for (const auto& d : settled) on_host_byte(static_cast<char>(d.value));
    }
    if (!field_line.empty()) match_fields();  // a last line without '\n'
    result.cycles_total = core.cycle();
    result.clock_hz = core.clock_hz();
    if (vcd) vcd->finish();
    result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    result.uart_bytes = uart.bytes_received();
    result.eeprom = rig.eeprom().read_all();
    result.report = parser.report();
    result.has_report = reports;
    const double sim_s = hil::cycles_to_s(result.cycles_total, core.clock_hz());
    avr_cycle_timer_cancel(core.raw(), &on_wall_check, &wall_guard);
    if (wall_guard.tripped) {
        result.exit = RunExit::kWallTimeout;
        result.message = fmt::format("wall-clock timeout after {} s (--wall-timeout) at t = {:.6f} simulated s",
                                     options.max_wall_seconds, sim_s);
    } else if (killed()) {
        result.exit = RunExit::kKilledByDebugger;
        result.message = fmt::format("killed by the debugger at cycle {} (t = {:.6f} s)", core.cycle(), sim_s);
    } else if (const auto failure = hil::describe_run_failure(hil::observe_run_end(stop, rig, stack_guard),
                                                              hil::FailureWording::kStandalone)) {
        result.exit = run_exit_of(failure->kind);
        result.message = failure->message;
    } else if (reports && parser.error()) {
        result.exit = RunExit::kReportMalformed;
        result.message = *parser.error();
    } else if (done) {
        result.exit = RunExit::kReportComplete;
    } else if (!completes) {
        result.exit = RunExit::kTimeLimit;  // the run it was asked for, complete
    } else {  // the time limit came first
        result.exit = RunExit::kTimeout;
        const std::string what =
            options.unity ? std::string(unity_watch.counts_seen()
                                            ? "Unity's OK or FAIL line never came after its counts"
                                            : "Unity's summary ('N Tests N Failures N Ignored', then OK or FAIL) "
                                              "never came")
            : contract->complete->report ? std::string("the firmware's report was not complete")
                                         : fmt::format("'{}' never came", *contract->complete->text);
        if (result.ready_cycle || !has_start) {
            result.message = fmt::format("timeout after {} simulated s: {} (raise --seconds?)",
                                         options.max_sim_seconds, what);
        } else {
            const auto& st = *contract->start;
            const std::string when = ready ? fmt::format("the firmware never returned from '{}'", ready_symbol)
                                     : st.after_text ? fmt::format("'{}' never came", *st.after_text)
                                                     : std::string("its time never came");
            result.message = fmt::format("timeout after {} simulated s: {}, so the start text was never sent",
                                         options.max_sim_seconds, when);
        }
    }

    // A gdb still attached and waiting learns that the program exited, with
    // the exit code this process will return.
    if (gdb) gdb->end_of_run(result.exit == RunExit::kReportComplete ? kExitOk : kExitFirmware);

    for (unsigned ch = 0; ch < 2; ++ch) result.encoder[ch] = rig.encoders().stats(ch);
    result.end_pose_truth = rig.robot().pose();
    result.loop_iterations = loop_iterations;
    if (period_count > 0) {
        result.mean_loop_period_s =
            hil::cycles_to_s(period_sum, core.clock_hz()) / static_cast<double>(period_count);
    }
    json loop_profile = nullptr;
    std::string loop_profile_csv;
    if (profiler) {
        std::vector<Cycles> write_cycles;
        for (const auto& w : rig.eeprom_timing().writes()) write_cycles.push_back(w.cycle);
        profiler->tag_eeprom_writes(write_cycles);
        result.loop_profile = profiler->iterations();
        loop_profile = loop_profile_json(result.loop_profile, core.clock_hz());
        loop_profile["eeprom_writes_all_tagged"] = rig.eeprom_timing().all_writes_recorded();
        loop_profile["mark"] = loop_mark_name;
        loop_profile_csv = loop_profile_table(result.loop_profile, core.clock_hz());
    }
    json function_profile = nullptr;
    std::string function_profile_txt;
    std::string callgrind_txt;
    if (function_profiler) {
        FunctionProfileContext context{core.clock_hz(), loop_mark_name, {}, {}};
        try {
            context.lines = profile_lines(elf.path(), *function_profiler);
        } catch (const std::exception& e) {
            context.lines_error = e.what();
            std::fprintf(stderr, "ddmr-hil: warning: no source lines in the profile: %s\n", e.what());
        }
        function_profile = function_profile_json(*function_profiler, context);
        function_profile["callgrind"] = {{"file", "callgrind.out"}, {"scope", callgrind_scope(*function_profiler)}};
        function_profile_txt = function_profile_text(*function_profiler, context);
        callgrind_txt = callgrind_profile(*function_profiler, context, elf.path().string());
        result.function_profile_top = ddmr::tools::function_profile_top(*function_profiler, context, options.profile_top);
    }
    const hil::IsrSummary isr_summary = isr_monitor.summary();
    json isr = isr_json(isr_summary);
    const RaceReport race = race_report(races, elf);
    isr["races"] = race.json;
    const json torn = torn_reads_summary(races);
    hil::EepromLogTiming log_timing;
    if (contract && contract->eeprom_log) {
        log_timing = hil::eeprom_log_timing(rig.eeprom_timing().latest_writes(), result.ready_cycle.value_or(0),
                                            core.clock_hz(), static_cast<int>(core.mcu().eeprom_bytes),
                                            *contract->eeprom_log);
    }
    // The EEPROM log, where the contract says the sketch keeps one.
    const auto log = contract && contract->eeprom_log
                         ? hil::decode_eeprom_log(result.eeprom, log_timing.sample_count, log_timing.times_s,
                                                  *contract->eeprom_log)
                         : std::vector<hil::EepromLogSample>{};
    result.eeprom_log_samples = log.size();
    result.eeprom_writes = rig.eeprom_timing().write_count();
    result.eeprom_writes_recorded = rig.eeprom_timing().writes().size();

    // --- Artifacts, each written atomically. ---
    const double mcycles_per_s =
        result.wall_seconds > 0 ? static_cast<double>(result.cycles_total) / result.wall_seconds / 1e6 : 0.0;
    json encoder = json::object();
    for (unsigned ch = 0; ch < 2; ++ch) {
        const auto& s = result.encoder[ch];
        const hil::EncoderWiring& w = config.board.wheel[ch].encoder;
        json pins = json::array();
        for (unsigned k = 0; k < w.signals(); ++k) pins.push_back(w.pin[k]);
        encoder[fmt::format("channel{}", ch + 1)] = {
            {"wheel", hil::wheel_name(ch)},
            {"type", w.kind == hil::EncoderKind::quadrature ? "quadrature"
                     : w.kind == hil::EncoderKind::single    ? "single"
                                                             : "none"},
            {"pin", w.signals() > 0 ? json(w.pin[0]) : json(nullptr)},
            {"pins", pins},
            {"edges_injected", s.edges_injected},
            {"isr_count", s.isr_count},
            {"lost_edges", s.lost_edges},
        };
    }
    const std::vector<std::string> wiring_warnings = rig.driver().wiring_warnings();
    for (const std::string& w : wiring_warnings) std::fprintf(stderr, "ddmr-hil: warning: %s\n", w.c_str());
    json summary = {
        {"firmware",
         {{"path", options.firmware.string()},
          {"sha256", sha256},
          {"flash_bytes", elf.memory_use().flash_bytes()},
          {"ram_bytes", elf.memory_use().ram_bytes()}}},
        {"protocol", contract ? "contract" : "none"},
        {"contract", contract ? json(contract->source) : json(nullptr)},
        {"case", test_case != 0 ? json(test_case) : json(nullptr)},
        {"plant_file", options.plant_file ? options.plant_file->string() : "(embedded defaults)"},
        {"pwm", options.pwm == plant::DriveMode::switched ? "switched" : "averaged"},
        {"eeprom_timing", options.eeprom_timing == hil::EepromTimingMode::kDatasheet ? "datasheet" : "instant"},
        {"coupling_step_cycles", rig.coupler().config().step_cycles},
        {"max_input_latency_cycles", rig.coupler().max_input_latency_cycles()},
        {"cycles_total", result.cycles_total},
        {"clock_hz", core.clock_hz()},
        {"sim_seconds", sim_s},
        {"wall_seconds", result.wall_seconds},
        {"mcycles_per_s", mcycles_per_s},
        {"exit_reason", to_string(result.exit)},
        {"exit_message", result.message},
        {"ready_cycle", result.ready_cycle ? json(*result.ready_cycle) : json(nullptr)},
        {"uart",
         {{"bytes", uart.bytes_received()},
          {"cycles_per_byte", uart.cycles_per_byte()},
          {"timing", options.uart_timing == hil::UartTiming::kChip ? "chip" : "simavr"},
          {"port", hil::serial_port_name(uart.usart().index)},
          {"bytes_not_delivered", uart.pending()},
          {"adapter_baud", adapter ? json(adapter->baud()) : json(nullptr)},
          {"framing_errors", adapter ? json(adapter->framing_errors()) : json(nullptr)}}},
        {"board",
         {{"file", config.board.source},
          {"name", core.board().key},
          {"mcu", core.mcu().name},
          {"clock_hz", core.clock_hz()},
          {"wiring_warnings", wiring_warnings}}},
        {"encoder", encoder},
        {"end_pose_truth", pose_json(result.end_pose_truth)},
        {"end_pose_firmware", result.end_pose_firmware ? pose_json(*result.end_pose_firmware) : json(nullptr)},
        {"loop_iterations", result.loop_iterations},
        {"mean_loop_period_s", result.mean_loop_period_s},
        {"eeprom_log_samples", result.eeprom_log_samples},
        {"eeprom_writes", result.eeprom_writes},
        {"eeprom_writes_recorded", result.eeprom_writes_recorded},
        {"loop_profile", loop_profile},
        {"vcd", options.vcd ? json(options.vcd->string()) : json(nullptr)},
        {"function_profile",
         function_profiler ? json{{"details", "profile.json"},
                                  {"control_loop_iterations", function_profiler->control_loop().iterations},
                                  {"max_stack_depth", function_profiler->max_depth_seen()},
                                  {"stack_overflows", function_profiler->stack_overflows()}}
                           : json(nullptr)},
        {"isr", {{"isr_share", static_cast<double>(isr_summary.isr_cycles) /
                                   static_cast<double>(std::max<Cycles>(1, isr_summary.observed_cycles()))},
                 {"torn_reads", torn},
                 {"races", {{"torn_observed", isr["races"]["torn_observed"]},
                            {"torn_possible", isr["races"]["torn_possible"]},
                            {"stale_reads", isr["races"]["stale_reads"]}}},
                 {"details", "isr.json"}}},
        {"plant_steps", rig.coupler().plant_steps()},
        {"firmware_report", reports ? report_json(result.report) : json(nullptr)},
        {"unity", result.unity    ? json{{"complete", true},
                                         {"tests", result.unity->tests},
                                         {"failures", result.unity->failures},
                                         {"ignored", result.unity->ignored},
                                         {"ok", result.unity->ok}}
                  : options.unity ? json{{"complete", false}}  // the summary never came
                                  : json(nullptr)},
        {"firmware_source", options.firmware_source},
        {"calls_to_address_0", zero_calls_json(zero_calls)},
        {"unasked_resets", unasked_resets_json(rig.reset_monitor())},
        {"report_fields", [&] {
             if (field_patterns.empty()) return json(nullptr);
             json f = json::object();
             for (std::size_t i = 0; i < field_patterns.size(); ++i) {
                 f[contract->report_fields[i].name] = field_values[i] ? json(*field_values[i]) : json(nullptr);
             }
             return f;
         }()},
        {"simavr_log",
         {{"errors", core.log().errors()},
          {"warnings", core.log().warnings()},
          {"first_messages", core.log().first_messages()}}},
    };
    uart_txt.commit();
    write_file_atomic(options.out_dir / "eeprom.bin",
                      std::string_view(reinterpret_cast<const char*>(result.eeprom.data()),
                                       result.eeprom.size()));
    if (contract && contract->eeprom_log) write_file_atomic(options.out_dir / "eeprom_log.csv", hil::eeprom_log_csv(log));
    if (profiler) write_file_atomic(options.out_dir / "loop_profile.csv", loop_profile_csv);
    if (function_profiler) {
        write_file_atomic(options.out_dir / "profile.json", function_profile.dump(2) + "\n");
        write_file_atomic(options.out_dir / "profile.txt", function_profile_txt);
        write_file_atomic(options.out_dir / "callgrind.out", callgrind_txt);
    }
    write_file_atomic(options.out_dir / "isr.json", isr.dump(2) + "\n");
    write_file_atomic(options.out_dir / "isr.md", hil::to_markdown(isr_summary) + race.markdown);
    if (trace_csv) trace_csv->commit();
    if (vcd_file) vcd_file->commit();
    truth_csv.commit();
    if (firmware_csv) firmware_csv->commit();
    write_file_atomic(options.out_dir / "summary.json", summary.dump(2) + "\n");
    return result;
}

}  // namespace ddmr::tools
