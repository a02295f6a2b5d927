#include "fast_forward_report.hpp"
#include "firmware_run.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/firmware_diagnostics.hpp"
#include "common/truth_csv.hpp"
#include "common/world_json.hpp"
#include "contract_watch.hpp"
#include "exit_codes.hpp"
#include "firmware_run_json.hpp"
#include "firmware_run_plan.hpp"
#include "hil/eeprom_log.hpp"
#include "hil/function_profiler.hpp"
#include "hil/loop_tracer.hpp"
#include "hil/session.hpp"
#include "hil/vcd_recorder.hpp"
#include "run_outputs.hpp"
#include "session_outputs.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
using hil::Cycles;
using nlohmann::json;

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


hil::SessionOptions session_options(const FirmwareRunOptions& options, const RunPlan& plan) {
    hil::SessionOptions o;
    o.instruments = options.instruments;
    o.adapter_baud = options.baud;
    o.eeprom_preload = plan.preload;
    o.time_limit = hil::s_to_cycles(options.max_sim_seconds, plan.board->clock_hz);
    o.wall_limit_s = options.max_wall_seconds;
    if (options.gdb_port) o.gdb = hil::GdbServerConfig{*options.gdb_port, options.gdb_attach_timeout_s};
    o.echo_simavr_log = options.echo_simavr_log;
    o.fast_forward = options.fast_forward;
    return o;
}

/// Why a run that should have completed did not, in one line.
std::string timeout_message(const RunPlan& plan, const FirmwareRunOptions& options, const ContractWatch& watch,
                            bool started) {
    const std::string what =
        options.unity ? std::string(watch.unity_counts_seen()
                                        ? "Unity's OK or FAIL line never came after its counts"
                                        : "Unity's summary ('N Tests N Failures N Ignored', then OK or FAIL) "
                                          "never came")
        : plan.contract->complete->report ? std::string("the firmware's report was not complete")
                                          : fmt::format("'{}' never came", *plan.contract->complete->text);
    if (started || !plan.has_start) {
        return fmt::format("timeout after {} simulated s: {} (raise --seconds?)", options.max_sim_seconds, what);
    }
    const auto& st = *plan.contract->start;
    const std::string when = plan.ready ? fmt::format("the firmware never returned from '{}'", plan.ready_symbol)
                             : st.after_text ? fmt::format("'{}' never came", *st.after_text)
                                             : std::string("its time never came");
    return fmt::format("timeout after {} simulated s: {}, so the start text was never sent", options.max_sim_seconds,
                       when);
}

/// The run's end, in RunExit terms: the session's own ends first, then
/// what the contract says of the run.
void classify_end(hil::SessionStop stop, const hil::Session& session, const RunPlan& plan,
                  const FirmwareRunOptions& options, const ContractWatch& watch, FirmwareRunResult& result) {
    switch (stop) {
        case hil::SessionStop::kWallLimit: result.exit = RunExit::kWallTimeout; break;
        case hil::SessionStop::kKilled: result.exit = RunExit::kKilledByDebugger; break;
        case hil::SessionStop::kFailure: result.exit = run_exit_of(session.failure()->kind); break;
        default: {
            if (plan.reports && watch.parser().error()) {
                result.exit = RunExit::kReportMalformed;
                result.message = *watch.parser().error();
            } else if (watch.done()) {
                result.exit = RunExit::kReportComplete;
            } else if (!plan.completes) {
                result.exit = RunExit::kTimeLimit;  // the run it was asked for, complete
            } else {  // the time limit came first
                result.exit = RunExit::kTimeout;
                result.message = timeout_message(plan, options, watch, result.ready_cycle.has_value());
            }
            return;
        }
    }
    result.message = session.end_message(stop);
}

/// The run: the boot up to the ready function's first return (where the
/// contract has one), the start text, then the run to its end.
hil::SessionStop run_session(hil::Session& session, const RunPlan& plan, Profilers& profilers,
                             const std::function<void()>& send_start, const std::function<void()>& between) {
    if (plan.ready) {
        const hil::SessionStop boot = session.run_to_first_return_from(*plan.ready);
        if (boot != hil::SessionStop::kCondition) return boot;
        send_start();
        if (between) between();
    } else if (profilers.loop && !plan.has_start) {
        profilers.loop->arm();  // every iteration from reset on
    }
    if (plan.has_start && plan.contract->start->at_s) {
        session.at(hil::s_to_cycles(*plan.contract->start->at_s, session.core().clock_hz()), send_start);
    }
    if (!between) return session.run(hil::Session::kNoTarget);
    const hil::Cycles chunk = hil::s_to_cycles(0.01, session.core().clock_hz());
    for (;;) {
        const hil::SessionStop stop = session.run(session.cycle() + chunk);
        if (stop != hil::SessionStop::kReachedCycle) return stop;
        between();
    }
}

/// The run's figures, read off the session at its end.
void collect_results(hil::Session& session, const RunPlan& plan, const ContractWatch& watch,
                     const LoopTraceOutput* loop_trace, FirmwareRunResult& result) {
    hil::RobotRig& rig = session.rig();
    result.cycles_total = session.cycle();
    result.clock_hz = session.core().clock_hz();
    result.wall_seconds = session.wall_seconds();
    result.uart_bytes = rig.uart().bytes_received();
    result.eeprom = rig.eeprom().read_all();
    result.report = watch.parser().report();
    result.has_report = plan.reports;
    result.unity = watch.unity();
    result.end_pose_firmware = watch.firmware_pose();
    for (unsigned ch = 0; ch < 2; ++ch) result.encoder[ch] = rig.encoders().stats(ch);
    result.end_pose_truth = rig.robot().pose();
    if (loop_trace != nullptr) {
        result.loop_iterations = loop_trace->iterations();
        result.mean_loop_period_s = loop_trace->mean_period_s();
    }
    result.eeprom_writes = rig.eeprom_timing().write_count();
    result.eeprom_writes_recorded = rig.eeprom_timing().writes().size();
}

/// The EEPROM log, where the contract says the sketch keeps one.
std::vector<hil::EepromLogSample> eeprom_log(hil::Session& session, const RunPlan& plan,
                                             const FirmwareRunResult& result) {
    if (!plan.contract || !plan.contract->eeprom_log) return {};
    hil::RobotRig& rig = session.rig();
    const hil::EepromLogTiming timing =
        hil::eeprom_log_timing(rig.eeprom_timing().latest_writes(), result.ready_cycle.value_or(0),
                               session.core().clock_hz(), static_cast<int>(session.core().mcu().eeprom_bytes),
                               *plan.contract->eeprom_log);
    return hil::decode_eeprom_log(result.eeprom, timing.sample_count, timing.times_s, *plan.contract->eeprom_log);
}

json unity_json(const FirmwareRunResult& result, const FirmwareRunOptions& options) {
    if (result.unity) {
        return json{{"complete", true},
                    {"tests", result.unity->tests},
                    {"failures", result.unity->failures},
                    {"ignored", result.unity->ignored},
                    {"ok", result.unity->ok}};
    }
    return options.unity ? json{{"complete", false}} : json(nullptr);  // the summary never came
}

json summary_json(hil::Session& session, const RunPlan& plan, const FirmwareRunOptions& options,
                  const FirmwareRunResult& result, const ContractWatch& watch, const ProfileOutputs& profile,
                  const Profilers& profilers, const IsrOutputs& isr, const std::vector<std::string>& wiring_warnings) {
    hil::RobotRig& rig = session.rig();
    hil::AvrCore& core = session.core();
    hil::UartLink& uart = rig.uart();
    const hil::HostAdapter* adapter = session.adapter();
    const double sim_s = hil::cycles_to_s(result.cycles_total, core.clock_hz());
    const double mcycles_per_s =
        result.wall_seconds > 0 ? static_cast<double>(result.cycles_total) / result.wall_seconds / 1e6 : 0.0;
    const auto& fp = profilers.functions;
    return json{
        {"firmware",
         {{"path", options.firmware.string()},
          {"sha256", plan.sha256},
          {"flash_bytes", plan.elf.memory_use().flash_bytes()},
          {"ram_bytes", plan.elf.memory_use().ram_bytes()}}},
        {"protocol", plan.contract ? "contract" : "none"},
        {"contract", plan.contract ? json(plan.contract->source) : json(nullptr)},
        {"case", plan.test_case != 0 ? json(plan.test_case) : json(nullptr)},
        {"plant_file", !options.plant_source.empty() ? options.plant_source
                       : options.plant_file       ? options.plant_file->string()
                                                  : std::string("(embedded defaults)")},
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
         {{"file", plan.config.board.source},
          {"name", core.board().key},
          {"mcu", core.mcu().name},
          {"clock_hz", core.clock_hz()},
          {"wiring_warnings", wiring_warnings}}},
        {"world", options.world_file ? json(options.world_file->string()) : json(nullptr)},
        {"contacts", plan.config.world.walls.empty() ? json(nullptr) : contacts_json(rig.robot())},
        {"encoder", encoder_json(plan.config.board, result.encoder)},
        {"end_pose_truth", pose_json(result.end_pose_truth)},
        {"end_pose_firmware", result.end_pose_firmware ? pose_json(*result.end_pose_firmware) : json(nullptr)},
        {"loop_iterations", result.loop_iterations},
        {"mean_loop_period_s", result.mean_loop_period_s},
        {"eeprom_log_samples", result.eeprom_log_samples},
        {"eeprom_writes", result.eeprom_writes},
        {"eeprom_writes_recorded", result.eeprom_writes_recorded},
        {"loop_profile", profile.loop_profile},
        {"vcd", options.vcd ? json(options.vcd->string()) : json(nullptr)},
        {"function_profile", fp ? json{{"details", "profile.json"},
                                       {"control_loop_iterations", fp->control_loop().iterations},
                                       {"max_stack_depth", fp->max_depth_seen()},
                                       {"stack_overflows", fp->stack_overflows()}}
                                : json(nullptr)},
        {"isr", isr.summary},
        {"fast_forward", fast_forward_json(core, result.cycles_total)},
        {"plant_steps", rig.coupler().plant_steps()},
        {"firmware_report", plan.reports ? report_json(result.report) : json(nullptr)},
        {"unity", unity_json(result, options)},
        {"firmware_source", options.firmware_source},
        {"calls_to_address_0", zero_calls_json(plan.zero_calls)},
        {"unasked_resets", unasked_resets_json(rig.reset_monitor())},
        {"report_fields", watch.fields_json()},
        {"simavr_log",
         {{"errors", core.log().errors()},
          {"warnings", core.log().warnings()},
          {"first_messages", core.log().first_messages()}}},
    };
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
        case RunExit::kStopped: return "stopped";
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

/// Everything one run holds; built in the order `run` has always built it.
struct FirmwareRun::State {
    FirmwareRunOptions options;
    RunPlan plan;  // every check before anything is written
    hil::Session session;
    std::optional<hil::LoopTracer> tracer;
    Profilers profilers;
    std::optional<VcdOutput> vcd;
    std::optional<TruthOutput> truth;
    std::optional<AtomicFileWriter> uart_txt;  ///< grows as the firmware writes: no copy held in memory
    std::optional<LoopTraceOutput> loop_trace;
    std::optional<TraceOutput> trace;
    std::optional<ContractWatch> watch;
    FirmwareRunResult result;
    bool started = false;  ///< the contract's start text went out (or it has none)
    bool driven = false;   ///< run_to_end ran: the contract drove the run
    bool finished = false;

    explicit State(FirmwareRunOptions o)
        : options(std::move(o)), plan(plan_firmware_run(options)),
          session(plan.elf, plan.config, session_options(options, plan)), profilers(session.core(), plan.loop_mark),
          started(!plan.has_start) {}

    void progress(const char* phase) {
        if (!options.progress) return;
        std::fprintf(stderr, "ddmr-hil run: %-8s t = %6.2f s of %.0f s simulated, %llu UART bytes\n", phase,
                     session.core().seconds(), options.max_sim_seconds,
                     static_cast<unsigned long long>(session.rig().uart().bytes_received()));
    }
    /// The contract's start text: once the firmware returns from its ready
    /// function (run up to that first), at an AVR time, or after a text.
    void send_start() {
        if (started) return;
        result.ready_cycle = session.core().cycle();
        progress("ready");
        if (profilers.loop) profilers.loop->arm();
        session.send(plan.start_text);
        started = true;
    }
    void check_and_wait();
    void open_outputs();
    void write_artifacts();
};

/// What can still be refused, and the debugger, before anything is written.
void FirmwareRun::State::check_and_wait() {
    // The contract's globals traced per iteration (firmware.csv).
    if (plan.loop_marker) tracer.emplace(session.rig().variables(), *plan.loop_marker, plan.traced);
    // --trace's globals: every name and size.
    for (const auto& v : plan.trace_vars) static_cast<void>(session.rig().variables().lookup(v.name, v.type));
    if (options.gdb_port) {
        std::fprintf(stderr,
                     "ddmr-hil: waiting for avr-gdb on 127.0.0.1:%u (loopback only): "
                     "avr-gdb -ex 'target remote 127.0.0.1:%u' %s\n",
                     unsigned{*options.gdb_port}, unsigned{*options.gdb_port}, options.firmware.c_str());
        session.wait_for_debugger();
    }
}

/// The streamed outputs (atomic: renamed into place at the end) and the observers.
void FirmwareRun::State::open_outputs() {
    prepare_output_dir(options.out_dir);
    hil::AvrCore& core = session.core();
    if (options.vcd) vcd.emplace(session, *options.vcd, profilers.loop ? &*profilers.loop : nullptr);
    truth.emplace(options.out_dir / "truth.csv", session.rig());
    uart_txt.emplace(options.out_dir / "uart.txt");
    if (tracer) {
        loop_trace.emplace(*tracer, plan, options.out_dir / "firmware.csv", core.clock_hz(),
                           vcd ? &vcd->recorder() : nullptr);
    }
    if (!plan.trace_vars.empty()) trace.emplace(session, plan, options);
    session.set_progress([this](Cycles) { progress("running"); });
    watch.emplace(session, plan, options.unity, *uart_txt, [this] { send_start(); });
    watch->set_driving(options.contract_drives);
    session.attach(*watch);
    session.attach(*truth);
    if (loop_trace) session.attach(*loop_trace);
    if (trace) session.attach(*trace);
    if (vcd) session.attach(*vcd);
    // --send bytes go out at their times (those due during the reference
    // sketch's boot at its ready point, after the start text).
    for (const auto& s : plan.sends) {
        session.at(hil::s_to_cycles(s.at_s, core.clock_hz()), [this, &s] { session.send(s.bytes); });
    }
}

/// Every artifact, each written atomically.
void FirmwareRun::State::write_artifacts() {
    const ProfileOutputs profile = profile_outputs(session, plan, options, profilers, result);
    const IsrOutputs isr = isr_outputs(session);
    const auto log = eeprom_log(session, plan, result);
    result.eeprom_log_samples = log.size();
    const std::vector<std::string> wiring_warnings = session.rig().warnings();
    for (const std::string& w : wiring_warnings) std::fprintf(stderr, "ddmr-hil: warning: %s\n", w.c_str());
    const json summary = summary_json(session, plan, options, result, *watch, profile, profilers, isr, wiring_warnings);
    const fs::path& out = options.out_dir;
    uart_txt->commit();
    const plant::World& world = session.rig().world();
    if (!world.lines.empty() || !world.walls.empty()) {
        write_file_atomic(out / "world.json", world_json(world).dump(2) + "\n");
    }
    write_file_atomic(out / "eeprom.bin",
                      std::string_view(reinterpret_cast<const char*>(result.eeprom.data()), result.eeprom.size()));
    if (plan.contract && plan.contract->eeprom_log) write_file_atomic(out / "eeprom_log.csv", hil::eeprom_log_csv(log));
    if (profilers.loop) write_file_atomic(out / "loop_profile.csv", profile.loop_profile_csv);
    if (profilers.functions) {
        write_file_atomic(out / "profile.json", profile.function_profile.dump(2) + "\n");
        write_file_atomic(out / "profile.txt", profile.function_profile_txt);
        write_file_atomic(out / "callgrind.out", profile.callgrind_txt);
    }
    if (session.isr_monitor() != nullptr) {
        write_file_atomic(out / "isr.json", isr.isr.dump(2) + "\n");
        write_file_atomic(out / "isr.md", isr.markdown);
    }
    if (trace) trace->commit();
    if (vcd) vcd->commit();
    truth->commit();
    if (loop_trace) loop_trace->commit();
    write_file_atomic(out / "summary.json", summary.dump(2) + "\n");
}

FirmwareRun::FirmwareRun(FirmwareRunOptions options) : s_(std::make_unique<State>(std::move(options))) {
    s_->check_and_wait();
    s_->open_outputs();
}

FirmwareRun::~FirmwareRun() = default;

hil::Session& FirmwareRun::session() { return s_->session; }
const RunPlan& FirmwareRun::plan() const { return s_->plan; }
const FirmwareRunOptions& FirmwareRun::options() const { return s_->options; }
bool FirmwareRun::finished() const { return s_->finished; }

void FirmwareRun::set_case(int test_case) {
    RunPlan& plan = s_->plan;
    if (s_->session.cycle() != 0) throw std::logic_error("the contract's case is set before the run starts");
    if (!(plan.has_start && !plan.contract->start->cases.empty())) {
        throw std::invalid_argument(fmt::format("case {}: the sketch contract {} takes no case", test_case,
                                                plan.contract ? plan.contract->source : std::string("(none)")));
    }
    plan.test_case = test_case;
    plan.start_text = plan.contract->start_text(test_case);  // refuses a case the contract does not list
    s_->watch->case_changed();
}

hil::LoopProfiler* FirmwareRun::loop_profiler() { return s_->profilers.loop ? &*s_->profilers.loop : nullptr; }

hil::SessionStop FirmwareRun::run_to_end(const std::function<void()>& between) {
    State& st = *s_;
    if (st.finished) throw std::logic_error("the run has finished: its artifacts are written");
    if (!st.plan.completes && st.options.notices) {
        std::fprintf(stderr,
                     "ddmr-hil: %s: %s, so it runs %g simulated s (--seconds) and ends with exit_reason time_limit\n",
                     st.options.firmware.c_str(),
                     st.plan.contract ? "the sketch contract says nothing about when a run is complete"
                                      : "no sketch contract (--contract FILE, docs/contracts.md)",
                     st.options.max_sim_seconds);
    }
    st.driven = true;
    st.watch->set_driving(true);
    return run_session(st.session, st.plan, st.profilers, [&st] { st.send_start(); }, between);
}

FirmwareRunResult FirmwareRun::finish(hil::SessionStop stop) {
    State& st = *s_;
    if (st.finished) throw std::logic_error("the run has finished: its artifacts are written");
    st.finished = true;
    ContractWatch& watch = *st.watch;
    if (watch.has_pose() && !watch.firmware_pose()) watch.read_pose();  // no text to read it at: the pose at the end
    st.session.flush_host_bytes();  // bytes still on the wire reach the adapter
    watch.finish();
    classify_end(stop, st.session, st.plan, st.options, watch, st.result);
    if (!st.driven && (stop == hil::SessionStop::kReachedCycle || stop == hil::SessionStop::kCondition) &&
        st.result.exit != RunExit::kReportComplete) {
        st.result.exit = RunExit::kStopped;  // a front end ran it to its own ends
        st.result.message.clear();
    }
    // A gdb still attached and waiting learns that the program exited, with
    // the exit code this process will return.
    if (hil::GdbServer* gdb = st.session.gdb()) {
        gdb->end_of_run(st.result.exit == RunExit::kReportComplete ? kExitOk : kExitFirmware);
    }
    collect_results(st.session, st.plan, watch, st.loop_trace ? &*st.loop_trace : nullptr, st.result);
    if (st.vcd) st.vcd->finish();
    st.write_artifacts();
    return st.result;
}

FirmwareRunResult run_firmware(const FirmwareRunOptions& options) {
    FirmwareRun run(options);
    return run.finish(run.run_to_end());
}

}  // namespace ddmr::tools
