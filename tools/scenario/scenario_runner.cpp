#include "scenario/scenario_runner.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <memory>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/csv_table.hpp"
#include "common/truth_csv.hpp"
#include "common/world_json.hpp"
#include "plant/units.hpp"
#include "scenario/fault_steps.hpp"
#include "scenario/scenario_signals.hpp"
#include "comparison.hpp"
#include "exit_codes.hpp"
#include "hil/atmega328p.hpp"
#include "hil/eeprom_log.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/plant_coupler.hpp"
#include "hil/robot_rig.hpp"
#include "hil/run_failure.hpp"
#include "hil/session.hpp"
#include "hil/serial_line.hpp"
#include "hil/stack_guard.hpp"
#include "hil/host_adapter.hpp"
#include "hil/race_detector.hpp"
#include "race_report.hpp"
#include "hil/vcd_recorder.hpp"
#include "hil/vcd_writer.hpp"
#include "hostsim/host_sim.hpp"
#include "scenario/scenario_expect.hpp"
#include "scenario/scenario_golden.hpp"
#include "fast_forward_report.hpp"
#include "scenario/scenario_result_json.hpp"
#include "scenario/step_failed.hpp"
#include "scenario/text_window.hpp"
#include "session_outputs.hpp"

namespace ddmr::tools::scenario {
namespace fs = std::filesystem;
using nlohmann::json;

const char* to_string(Verdict v) {
    switch (v) {
        case Verdict::kPass: return "pass";
        case Verdict::kFail: return "fail";
        case Verdict::kFirmware: return "firmware";
    }
    return "?";
}

int exit_code(Verdict v) {
    switch (v) {
        case Verdict::kPass: return kExitOk;
        case Verdict::kFail: return kExitCheckFailed;
        case Verdict::kFirmware: return kExitFirmware;
    }
    return kExitFirmware;
}

namespace {

/// Why a run segment ended early.
enum class Halt { kNone, kFailSerial, kFirmware };

/// The failure window: the last simulated seconds before the end of a
/// scenario that did not pass, as a VCD.
constexpr double kVcdWindowS = 0.5;

/// A wait without its own timeout: only the scenario's timeout ends it.
constexpr Cycles kNever = ~Cycles{0};


/// The data-space PIN/DDR/PORT registers and bit of an Uno pin.
hil::VarType default_type(const hil::ElfImage& elf, const std::string& name) {
    const auto sym = elf.find(name);
    if (!sym) throw StepFailed{Verdict::kFail, fmt::format("the firmware has no symbol '{}'", name)};
    const auto type = hil::default_var_type(sym->size, hil::FourByteDefault::kNone);
    if (!type) {
        throw StepFailed{Verdict::kFail, fmt::format("'{}' has {} bytes: give its type (type: int32, uint32 or float)",
                                                     name, sym->size)};
    }
    return *type;
}

class ScenarioRun final : public hil::SessionObserver {
public:
    ScenarioRun(const Scenario& s, const fs::path& out_dir, bool progress, bool update_golden)
        : s_(s), out_dir_(out_dir), progress_(progress), update_golden_(update_golden),
          elf_(hil::ElfImage::read(s.firmware)) {
        const hil::BoardDescription& board = hil::board_description(s.board.model);
        elf_.require_mcu(*board.mcu, board.key);
        const hil::RigConfig config = rig_config_of(s);
        hil::SessionOptions options;
        options.adapter_baud = s.baud;
        if (s.eeprom_preload) options.eeprom_preload = hil::EepromPort::load_image(*s.eeprom_preload, *board.mcu);
        options.time_limit = s.timeout;
        options.fast_forward = s.fast_forward;
        session_ = std::make_unique<hil::Session>(elf_, config, std::move(options));
        session_->set_failure_wording(hil::FailureWording::kInStep);  // the step's failure line gives the time
        rig_ = &session_->rig();
        signals_.emplace(*rig_);
        faults_.emplace(*session_);
        if (s.needs_loop_profile()) {
            const auto mark = elf_.require("delay");
            profiler_.emplace(rig_->core(), mark);
        }
        // The last kVcdWindowS of pins, PWM, ISRs, kept in memory and written
        // only if the scenario does not pass.
        hil::VcdConfig vcd_config;
        vcd_config.clock_hz = rig_->core().clock_hz();
        vcd_config.window.last_cycles = hil::s_to_cycles(kVcdWindowS, vcd_config.clock_hz);
        vcd_writer_.emplace([this](std::string_view text) { vcd_text_.append(text); }, vcd_config);
        vcd_.emplace(*rig_, elf_, *vcd_writer_, profiler_ ? &*profiler_ : nullptr);
        session_->attach(*this);
    }
    ScenarioRun(const ScenarioRun&) = delete;
    ScenarioRun& operator=(const ScenarioRun&) = delete;
    ~ScenarioRun() override = default;

    ScenarioResult run() {
        ScenarioResult r;
        r.name = s_.name;
        r.file = s_.file;
        const auto wall0 = std::chrono::steady_clock::now();
        prepare_output_dir(out_dir_);
        uart_txt_.emplace(out_dir_ / "uart.txt");
        truth_.emplace(out_dir_ / "truth.csv", *rig_);
        session_->attach(*truth_);
        for (const Step& step : s_.steps) {
            StepOutcome o{step.line, step.kind, step.text, false, 0, {}};
            current_line_ = step.line;
            try {
                o.message = execute(step);
                o.passed = true;
            } catch (const StepFailed& f) {
                o.message = f.message;
                r.verdict = f.verdict;
            }
            o.cycle = core().cycle();
            r.steps.push_back(o);
            if (progress_) {
                std::fprintf(stderr, "  [%s] %s line %d %s t=%.3f s%s%s\n", s_.name.c_str(),
                             o.passed ? "ok  " : "FAIL", o.line, o.kind.c_str(), seconds(o.cycle),
                             o.message.empty() ? "" : ": ", o.message.c_str());
            }
            if (!o.passed) {
                r.message = fmt::format("{}:{}: {} failed at t={:.6f} s: {}", s_.file.string(), o.line, o.kind,
                                        seconds(o.cycle), o.message);
                break;
            }
        }
        session_->flush_host_bytes();  // bytes still on the wire reach the adapter
        if (!line_.empty()) check_fail_patterns(line_.view(), core().cycle());  // a last line without \n
        if (halt_ == Halt::kFailSerial && r.verdict == Verdict::kPass) {
            r.verdict = Verdict::kFail;
            r.message = fmt::format("{}: {}", s_.file.string(), halt_message_);
        }
        r.cycles = core().cycle();
        r.sim_seconds = seconds(r.cycles);
        r.clock_hz = rig_->core().clock_hz();
        r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
        r.uart_bytes = text_.size();
        r.framing_errors = session_->adapter()->framing_errors();
        if (update_golden_) apply_golden(s_, golden_, r);
        write_artifacts(r);
        truth_->commit();
        return r;
    }

private:
    hil::AvrCore& core() { return rig_->core(); }
    double seconds(Cycles c) const { return hil::cycles_to_s(c, rig_->core().clock_hz()); }
    /// Cycles (a count or a mean) in microseconds at the board's clock.
    double us(Cycles cycles) const { return hil::cycles_to_s(cycles, rig_->core().clock_hz()) * 1e6; }
    double us(double cycles) const { return cycles * 1e6 / rig_->core().clock_hz(); }

    // --- the session's observer: what the adapter receives, each boundary --
    void on_host_byte(char c, Cycles cycle) override {
        text_.push_back(c);
        uart_txt_->write(std::string_view(&c, 1));
        if (c == '\n') {
            check_fail_patterns(line_.view(), cycle);
            line_.clear();
        } else if (c != '\r') {
            line_.push_back(c);
        }
        // A match that ends with this byte, after the previous wait's (any
        // earlier one was found before the run segment began).
        if (wait_text_ && text_.size() >= cursor_ + wait_text_->size() && text_.ends_with(*wait_text_)) {
            session_->interrupt();
        }
    }
    void on_truth(const hil::TruthSample& t) override { signals_->on_truth(t); }
    void on_boundary(Cycles c) override {
        vcd_->on_boundary(c);
        if (!unsent_.empty() && receiver_enabled()) {
            session_->send(unsent_);
            unsent_.clear();
        }
    }
    void check_fail_patterns(std::string_view line, Cycles cycle) {
        if (halt_ != Halt::kNone) return;
        for (const auto& [pattern, re] : fail_patterns_) {
            if (std::regex_search(line.begin(), line.end(), re)) {
                halt_ = Halt::kFailSerial;
                halt_message_ = fmt::format("fail-serial '{}' matched the line '{}' at t={:.6f} s", pattern, line,
                                            seconds(cycle));
                session_->end_run();
                return;
            }
        }
    }

    // --- timed actions and the run ------------------------------------------
    bool receiver_enabled() { return session_->adapter()->receiver_enabled(); }
    void at(Cycles cycle, std::function<void()> action) { session_->at(cycle, std::move(action)); }
    /// Runs to `target` or until `done()` (checked whenever the run stops
    /// early; with `poll`, also at every coupling boundary); throws
    /// StepFailed on a firmware failure, the scenario timeout or a
    /// fail-serial match. Returns true if done() became true.
    bool advance(Cycles target, const std::function<bool()>& done = {}, bool poll = false) {
        const hil::SessionStop stop = session_->run(target, hil::RunCondition{done, poll});
        switch (stop) {
            case hil::SessionStop::kCondition: return true;
            case hil::SessionStop::kReachedCycle: return false;
            case hil::SessionStop::kTimeLimit:
                timed_out_ = true;
                throw StepFailed{Verdict::kFirmware,
                                 fmt::format("timeout after {} simulated s (the scenario's timeout)", seconds(s_.timeout))};
            case hil::SessionStop::kEnded: throw StepFailed{Verdict::kFail, halt_message_};  // fail-serial
            default: throw StepFailed{Verdict::kFirmware, session_->end_message(stop)};
        }
    }

    // --- steps ------------------------------------------------------------
    std::string execute(const Step& step) {
        return std::visit([&](const auto& a) { return run_step(a); }, step.action);
    }

    std::string run_step(const Delay& d) {
        advance(core().cycle() + d.duration);
        return {};
    }
    std::string run_step(const WriteSerial& w) {
        if (!armed_) {
            if (profiler_) profiler_->arm();
            origin_cycle_ = core().cycle();
            armed_ = true;
        }
        if (!receiver_enabled()) {
            unsent_ += w.text;  // the adapter sends once the firmware listens
            return "held until the firmware enables its receiver";
        }
        const std::string bytes = session_->send(w.text);  // the adapter's frames as the firmware receives them
        if (bytes != w.text) return fmt::format("the firmware's receiver made {} byte(s) of it", bytes.size());
        return {};
    }
    /// "received N bytes (M framing errors), ending '...'": the last 60
    /// received characters, escaped (\r, \n shown as such).
    std::string received_tail() const {
        const std::string_view seen = text_.view();
        const std::string tail = seen.size() > 60 ? "..." + std::string(seen.substr(seen.size() - 60)) : std::string(seen);
        return fmt::format("received {} bytes ({} framing errors), ending '{}'", text_.size(),
                           session_->adapter()->framing_errors(),
                           printable(tail));
    }
    std::string run_step(const WaitSerial& w) {
        const Cycles start = core().cycle();
        wait_text_ = w.text;
        const Cycles end = w.timeout == 0 ? kNever : start + w.timeout;
        bool found = false;
        try {
            found = advance(end, [&] { return text_.find(w.text, cursor_).has_value(); });
        } catch (const StepFailed&) {
            wait_text_.reset();
            // The scenario's timeout while waiting: the text never came (a
            // failed expectation, with what did come), not a firmware error.
            if (!timed_out_) throw;
            throw StepFailed{Verdict::kFail, fmt::format("'{}' never came: the scenario's timeout ({} simulated s) came "
                                                         "first; {}",
                                                         printable(w.text), seconds(s_.timeout), received_tail())};
        }
        wait_text_.reset();
        if (!found) {
            throw StepFailed{Verdict::kFail, fmt::format("expected '{}' within {:.3f} s; {}", printable(w.text),
                                                         seconds(w.timeout), received_tail())};
        }
        cursor_ = *text_.find(w.text, cursor_) + w.text.size();
        return {};
    }
    std::string run_step(const ExpectWarning& e) {
        const std::regex re(e.pattern);
        const std::vector<std::string> warnings = rig_->warnings();
        for (const std::string& w : warnings) {
            if (std::regex_search(w, re)) return w;
        }
        throw StepFailed{Verdict::kFail, fmt::format("expected a wiring warning matching /{}/; there are {}{}", e.pattern,
                                                     warnings.size(), warnings.empty() ? "" : ": " + warnings.front())};
    }
    std::string run_step(const ExpectSerial& e) {
        const std::string_view seen = text_.view();  // the last kSerialWindowBytes
        if (!std::regex_search(seen.begin(), seen.end(), std::regex(e.pattern))) {
            throw StepFailed{Verdict::kFail, fmt::format("expected the output to match /{}/; it does not: {}",
                                                         printable(e.pattern), received_tail())};
        }
        return {};
    }
    std::string run_step(const FailSerial& f) {
        fail_patterns_.emplace_back(f.pattern, std::regex(f.pattern));
        return {};
    }
    /// Whether `pin` feeds one of the board's motor driver inputs.
    bool driver_pin(int pin) const {
        for (const hil::WheelWiring& w : rig_->config().board.wheel) {
            for (const hil::InputWire& in : w.motor.input) {
                if (in.on_pin() && in.pin == pin) return true;
            }
        }
        return false;
    }
    bool pin_level(int pin) {
        if (driver_pin(pin)) {
            hil::PinWaveforms& pins = rig_->driver().pins();
            pins.advance_to(core().cycle());
            if (pins.timer_driven(pin)) return pins.level_at(pin, core().cycle());
        }
        const hil::PinInfo p = *hil::board_pin(core().board(), pin);  // the step's pin was checked when the scenario was loaded
        const bool output = hil::atmega328p::bit_set(core().data(p.ddr_register), p.bit);
        return hil::atmega328p::bit_set(core().data(output ? p.port_register : p.pin_register), p.bit);
    }
    std::string run_step(const WaitPin& w) {
        const Cycles start = core().cycle();
        const Cycles end = w.timeout == 0 ? kNever : start + w.timeout;
        const bool ok = advance(end, [&] { return pin_level(w.pin) == w.value; }, /*poll=*/true);
        if (!ok) {
            throw StepFailed{Verdict::kFail, fmt::format("expected pin {} to become {} within {:.3f} s; it stayed {}",
                                                         w.pin, w.value ? 1 : 0, seconds(w.timeout),
                                                         pin_level(w.pin) ? 1 : 0)};
        }
        return fmt::format("(polled every {} cycles)", rig_->coupler().config().step_cycles);
    }
    std::string run_step(const ExpectPin& e) {
        const bool level = pin_level(e.pin);
        if (level != e.value) {
            throw StepFailed{Verdict::kFail, fmt::format("expected pin {} = {}, got {}", e.pin, e.value ? 1 : 0, level ? 1 : 0)};
        }
        return {};
    }
    std::string run_step(const ExpectPart& e) {
        const bool level = rig_->parts().output(e.part, e.port).level_at(core().cycle());
        if (level != e.value) {
            throw StepFailed{Verdict::kFail, fmt::format("expected part {}'s {} = {}, got {}", e.part, e.port,
                                                         e.value ? 1 : 0, level ? 1 : 0)};
        }
        return {};
    }
    std::string run_step(const ExpectPwm& e) {
        if (!driver_pin(e.pin)) {
            throw StepFailed{Verdict::kFail, fmt::format("pin {} is not a motor driver input on this board", e.pin)};
        }
        hil::PinWaveforms& pins = rig_->driver().pins();
        pins.advance_to(core().cycle());
        const double duty = pins.duty(e.pin);
        if (std::abs(duty - e.duty) > e.tol) {
            throw StepFailed{Verdict::kFail,
                             fmt::format("expected pin {} duty {:.4f} +- {:.4f}, got {:.4f}", e.pin, e.duty, e.tol, duty)};
        }
        return fmt::format("duty {:.4f}", duty);
    }
    std::string run_step(const ExpectVar& e) {
        const hil::VarType type = e.type ? *e.type : default_type(elf_, e.name);
        double v = 0.0;
        try {
            v = rig_->variables().read(e.name, type);
        } catch (const std::exception& ex) {
            throw StepFailed{Verdict::kFail, ex.what()};
        }
        if (!holds(v, e.op, e.value)) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} {} {:.9g}, got {:.9g}", e.name, to_string(e.op), e.value, v)};
        }
        return fmt::format("{} = {:.9g}", e.name, v);
    }
    std::string run_step(const ExpectPose& e) {
        plant::Pose p;
        if (e.source == PoseSource::kTruth) {
            p = rig_->robot().pose();
        } else {
            const auto& vars = rig_->variables();
            p = {vars.read("Ex", hil::VarType::kFloat), vars.read("Ey", hil::VarType::kFloat),
                 vars.read("Theta", hil::VarType::kFloat)};
        }
        const char* src = e.source == PoseSource::kTruth ? "truth" : "firmware";
        if (update_golden_) {
            golden_.push_back({current_line_, {}, {}, p});
            return fmt::format("{} pose ({:.4f}, {:.4f}) theta {:.4f}: recorded", src, p.x_m, p.y_m, p.theta_rad);
        }
        const double d = std::hypot(p.x_m - e.x_m, p.y_m - e.y_m);
        if (d > e.tol_m || (e.theta_rad && std::abs(p.theta_rad - *e.theta_rad) > e.tol_rad)) {
            throw StepFailed{Verdict::kFail,
                             fmt::format("expected the {} pose within {} m of ({:.4f}, {:.4f}){}; got ({:.4f}, {:.4f}) "
                                         "theta {:.4f} rad, {:.4f} m away",
                                         src, e.tol_m, e.x_m, e.y_m,
                                         e.theta_rad ? fmt::format(", theta {:.4f} +- {}", *e.theta_rad, e.tol_rad) : "",
                                         p.x_m, p.y_m, p.theta_rad, d)};
        }
        return fmt::format("{} pose ({:.4f}, {:.4f}) theta {:.4f}, {:.4f} m away", src, p.x_m, p.y_m, p.theta_rad, d);
    }
    std::vector<hil::EepromLogSample> eeprom_log() {
        const hil::EepromImage image = rig_->eeprom().read_all();
        const hil::EepromLogTiming timing =
            hil::eeprom_log_timing(rig_->eeprom_timing().latest_writes(), origin_cycle_, core().clock_hz(),
                                   static_cast<int>(core().mcu().eeprom_bytes));
        return hil::decode_eeprom_log(image, timing.sample_count, timing.times_s);
    }
    std::string run_step(const ExpectEeprom& e) {
        if (update_golden_) {
            std::string note;
            if (e.bin) {
                const hil::EepromImage image = rig_->eeprom().read_all();
                golden_.push_back({current_line_, *e.bin, std::string(image.begin(), image.end()), {}});
                note = fmt::format("{} bytes", image.size());
            }
            if (e.log) {
                const auto log = eeprom_log();
                golden_.push_back({current_line_, *e.log, hil::eeprom_log_csv(log), {}});
                note += fmt::format("{}{} log samples", note.empty() ? "" : ", ", log.size());
            }
            return note + ": recorded";
        }
        return expect_eeprom(rig_->eeprom().read_all(), eeprom_log(), e);
    }
    std::string run_step(const ExpectCompare& e) { return expect_compare(s_, eeprom_log(), e); }
    std::string run_step(const ExpectLoop& e) { return expect_loop(*session_, *profiler_, e); }
    std::string run_step(const ExpectIsr& e) { return expect_isr(*session_->isr_monitor(), e); }
    std::string run_step(const ExpectNoTornReads& e) { return expect_no_torn_reads(*session_->race_detector(), e); }
    std::string run_step(const ExpectEncoders& e) {
        uint64_t lost = 0;
        for (unsigned ch = 0; ch < 2; ++ch) lost += rig_->encoders().stats(ch).lost_edges;
        if (lost > e.max_lost) throw StepFailed{Verdict::kFail, fmt::format("expected at most {} lost encoder edges, {} were lost", e.max_lost, lost)};
        return fmt::format("{} edges lost", lost);
    }
    /// A signal now, as truth.csv would write it.
    double signal_now(const std::string& name) { return signals_->now(name); }
    std::string run_step(const Measure& m) {
        signals_->measure(m.signal);
        return {};
    }
    std::string run_step(const ExpectStats& e) { return signals_->expect_stats(e); }
    std::string run_step(const WaitUntil& w) {
        const Cycles start = core().cycle();
        const auto met = [&] { return holds(signal_now(w.signal), w.op, w.value); };
        const Cycles end = w.timeout == 0 ? kNever : start + w.timeout;
        bool ok = false;
        try {
            ok = advance(end, met, /*poll=*/true);
        } catch (StepFailed& f) {  // the scenario's timeout or a firmware failure: say what the signal was
            f.message += fmt::format("; {} was {:.9g}", w.signal, signal_now(w.signal));
            throw;
        }
        if (!ok) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} {} {:.9g} within {:.3f} s; it was {:.9g}", w.signal,
                                                         to_string(w.op), w.value, seconds(w.timeout),
                                                         signal_now(w.signal))};
        }
        return fmt::format("{} = {:.9g} (polled every {} cycles)", w.signal, signal_now(w.signal),
                           rig_->coupler().config().step_cycles);
    }
    std::string run_step(const ExpectSignal& e) {
        const double v = signal_now(e.signal);
        if (e.between.set()) {
            if (!e.between.contains(v)) {
                throw StepFailed{Verdict::kFail, fmt::format("expected {} in [{:.9g}, {:.9g}], got {:.9g}", e.signal,
                                                             *e.between.min, *e.between.max, v)};
            }
        } else if (!holds(v, e.op, e.value)) {
            throw StepFailed{Verdict::kFail,
                             fmt::format("expected {} {} {:.9g}, got {:.9g}", e.signal, to_string(e.op), e.value, v)};
        }
        return fmt::format("{} = {:.9g}", e.signal, v);
    }
    /// The steps that act on the robot and its world (fault_steps.hpp).
    template <class Action>
    auto run_step(const Action& a) -> decltype(std::declval<FaultSteps&>().run(a)) {
        return faults_->run(a);
    }
    std::string run_step(const Reset&) {
        core().reset();  // parts re-arm through their reset listeners; EEPROM and plant keep their state
        return fmt::format("reset #{}", core().resets());
    }

    void write_artifacts(const ScenarioResult& r) {
        json result = scenario_result_json(s_, r, rig_->warnings());
        result["fast_forward"] = fast_forward_json(core(), r.cycles);
        const hil::EepromImage image = rig_->eeprom().read_all();
        uart_txt_->commit();
        write_file_atomic(out_dir_ / "eeprom.bin",
                          std::string_view(reinterpret_cast<const char*>(image.data()), image.size()));
        const RaceReport race = race_report(*session_->race_detector(), elf_);
        write_file_atomic(out_dir_ / "isr.md", hil::to_markdown(session_->isr_monitor()->summary()) + race.markdown);
        write_file_atomic(out_dir_ / "eeprom_log.csv", hil::eeprom_log_csv(eeprom_log()));
        // wall time is not deterministic: it goes to stdout, not into result.json
        if (r.verdict != Verdict::kPass) {
            vcd_->finish();
            write_file_atomic(out_dir_ / "failure_window.vcd", vcd_text_);
        }
        const plant::World& world = rig_->world();
        if (!world.lines.empty() || !world.walls.empty()) {
            write_file_atomic(out_dir_ / "world.json", world_json(world).dump(2) + "\n");
        }
        write_file_atomic(out_dir_ / "result.json", result.dump(2) + "\n");
    }

    const Scenario& s_;
    fs::path out_dir_;
    bool progress_;
    bool update_golden_ = false;
    std::vector<Golden> golden_;
    int current_line_ = 0;  ///< the step being run
    hil::ElfImage elf_;
    std::unique_ptr<hil::Session> session_;
    hil::RobotRig* rig_ = nullptr;  ///< the session's
    std::optional<hil::LoopProfiler> profiler_;
    std::string vcd_text_;
    std::optional<hil::VcdWriter> vcd_writer_;
    std::optional<hil::VcdRecorder> vcd_;
    std::optional<TruthOutput> truth_;
    std::optional<RigSignals> signals_;
    std::optional<FaultSteps> faults_;  ///< after the session: it holds it
    bool armed_ = false;
    TextWindow text_{kSerialWindowBytes};  ///< the received text's end (uart.txt has it all)
    TextWindow line_{kSerialWindowBytes};  ///< the line being received, without \r
    std::optional<AtomicFileWriter> uart_txt_;
    std::string unsent_;  ///< written before the firmware enabled its receiver
    uint64_t cursor_ = 0;  ///< position in the received text after the previous wait-serial's match
    bool timed_out_ = false;  ///< the scenario's timeout was reached
    std::optional<std::string> wait_text_;
    std::vector<std::pair<std::string, std::regex>> fail_patterns_;
    Halt halt_ = Halt::kNone;
    std::string halt_message_;
    Cycles origin_cycle_ = 0;  ///< the first write-serial: the EEPROM log's time origin
};

}  // namespace

ScenarioResult run_scenario(const Scenario& s, const fs::path& out_dir, bool progress, bool update_golden) {
    ScenarioRun run(s, out_dir, progress, update_golden);
    return run.run();
}

}  // namespace ddmr::tools::scenario
