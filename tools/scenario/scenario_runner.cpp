#include "scenario/scenario_runner.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <regex>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/csv_table.hpp"
#include "common/truth_csv.hpp"
#include "comparison.hpp"
#include "exit_codes.hpp"
#include "hil/atmega328p.hpp"
#include "hil/eeprom_log.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/plant_coupler.hpp"
#include "hil/robot_rig.hpp"
#include "hil/run_failure.hpp"
#include "hil/serial_line.hpp"
#include "hil/stack_guard.hpp"
#include "hil/host_adapter.hpp"
#include "hil/race_detector.hpp"
#include "race_report.hpp"
#include "hil/vcd_recorder.hpp"
#include "hil/vcd_writer.hpp"
#include "hostsim/host_sim.hpp"
#include "scenario/text_window.hpp"

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

/// A step that did not hold: ends the scenario with `verdict`.
struct StepFailed {
    Verdict verdict;
    std::string message;
};

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

class Session {
public:
    Session(const Scenario& s, const fs::path& out_dir, bool progress, bool update_golden)
        : s_(s), out_dir_(out_dir), progress_(progress), update_golden_(update_golden),
          elf_(hil::ElfImage::read(s.firmware)) {
        const hil::BoardDescription& board = hil::board_description(s.board.model);
        elf_.require_mcu(*board.mcu, board.key);
        if (s.eeprom_preload) preload_ = hil::EepromPort::load_image(*s.eeprom_preload, *board.mcu);
        hil::RigConfig config;
        config.plant = s.plant;
        config.board = s.board;
        config.coupler.mode = s.pwm;
        config.eeprom_timing = s.eeprom_timing;
        config.host_usart = s.serial_usart;
        rig_.emplace(elf_, config);
        adapter_.emplace(rig_->core(), rig_->uart().usart(), s.baud);
        if (preload_) rig_->eeprom().preload(*preload_);
        isr_.emplace(rig_->core(), elf_);
        stack_guard_.emplace(rig_->core(), elf_);
        races_.emplace(rig_->core(), elf_);
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
        rig_->uart().set_listener([this](const hil::UartByte& b) { on_firmware_byte(b); });
        rig_->coupler().set_boundary_hook([this](Cycles c) { on_boundary(c); });
    }

    ScenarioResult run() {
        ScenarioResult r;
        r.name = s_.name;
        r.file = s_.file;
        const auto wall0 = std::chrono::steady_clock::now();
        prepare_output_dir(out_dir_);
        uart_txt_.emplace(out_dir_ / "uart.txt");
        AtomicFileWriter truth(out_dir_ / "truth.csv");
        truth.write(truth_csv_header(/*with_drive=*/true));
        std::string row;
        rig_->coupler().set_truth_sink([&](const hil::TruthSample& t) {
            row.clear();
            append_truth_row(row, t, /*with_drive=*/true);
            truth.write(row);
        });
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
        // Bytes still on the wire reach the adapter.
        std::vector<hil::LineByte> tail;
        adapter_->flush(tail);
        for (const auto& b : tail) receive(b);
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
        r.framing_errors = adapter_->framing_errors();
        if (update_golden_) apply_golden(r);
        write_artifacts(r);
        truth.commit();
        return r;
    }

private:
    hil::AvrCore& core() { return rig_->core(); }
    double seconds(Cycles c) const { return hil::cycles_to_s(c, rig_->core().clock_hz()); }
    /// Cycles (a count or a mean) in microseconds at the board's clock.
    double us(Cycles cycles) const { return hil::cycles_to_s(cycles, rig_->core().clock_hz()) * 1e6; }
    double us(double cycles) const { return cycles * 1e6 / rig_->core().clock_hz(); }

    // --- serial: firmware -> adapter ------------------------------------
    void on_firmware_byte(const hil::UartByte& b) {
        scratch_.clear();
        adapter_->on_firmware_byte(b, scratch_);
        for (const auto& lb : scratch_) receive(lb);
    }
    void receive(const hil::LineByte& b) {
        const char c = static_cast<char>(b.value);
        text_.push_back(c);
        uart_txt_->write(std::string_view(&c, 1));
        if (b.value == '\n') {
            check_fail_patterns(line_.view(), static_cast<Cycles>(b.cycle));
            line_.clear();
        } else if (b.value != '\r') {
            line_.push_back(c);
        }
        // A match that ends with this byte, after the previous wait's (any
        // earlier one was found before the run segment began).
        if (wait_text_ && text_.size() >= cursor_ + wait_text_->size() && text_.ends_with(*wait_text_)) {
            core().request_stop();
        }
    }
    void check_fail_patterns(std::string_view line, Cycles cycle) {
        if (halt_ != Halt::kNone) return;
        for (const auto& [pattern, re] : fail_patterns_) {
            if (std::regex_search(line.begin(), line.end(), re)) {
                halt_ = Halt::kFailSerial;
                halt_message_ = fmt::format("fail-serial '{}' matched the line '{}' at t={:.6f} s", pattern, line,
                                            seconds(cycle));
                core().request_stop();
                return;
            }
        }
    }

    // --- timed actions and the boundary poll -----------------------------
    bool receiver_enabled() const { return adapter_->receiver_enabled(); }
    std::string as_firmware_receives(const std::string& text) const { return adapter_->as_firmware_receives(text); }
    void on_boundary(Cycles c) {
        vcd_->on_boundary(c);
        scratch_.clear();
        adapter_->settle(c, scratch_);  // bytes whose stop bit has been sampled
        for (const auto& lb : scratch_) receive(lb);
        if (!unsent_.empty() && receiver_enabled()) {
            rig_->uart().send(as_firmware_receives(unsent_));
            unsent_.clear();
        }
        if (boundary_condition_ && boundary_condition_()) core().request_stop();
    }
    void at(Cycles cycle, std::function<void()> action) {
        timed_.push_back({cycle, std::move(action)});
        std::stable_sort(timed_.begin(), timed_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    /// Runs to `target` or until `done()` (checked whenever the run stops
    /// early); throws StepFailed on a firmware failure, the scenario timeout
    /// or a fail-serial match. Returns true if done() became true.
    bool advance(Cycles target, const std::function<bool()>& done = {}) {
        while (true) {
            if (done && done()) return true;
            if (core().cycle() >= target) return false;
            if (core().cycle() >= s_.timeout) {
                timed_out_ = true;
                throw StepFailed{Verdict::kFirmware,
                                 fmt::format("timeout after {} simulated s (the scenario's timeout)", seconds(s_.timeout))};
            }
            Cycles next = std::min(target, s_.timeout);
            if (!timed_.empty()) next = std::min(next, std::max(timed_.front().first, core().cycle()));
            const hil::RunStop stop = next > core().cycle() ? core().run_until(next) : hil::RunStop::kReachedCycle;
            // The step's failure line gives the time: the short wording.
            if (const auto failure = hil::describe_run_failure(hil::observe_run_end(stop, *rig_, *stack_guard_),
                                                               hil::FailureWording::kInStep)) {
                throw StepFailed{Verdict::kFirmware, failure->message};
            }
            if (halt_ == Halt::kFailSerial) throw StepFailed{Verdict::kFail, halt_message_};
            clear_stop();
            while (!timed_.empty() && timed_.front().first <= core().cycle()) {
                auto action = std::move(timed_.front().second);
                timed_.erase(timed_.begin());
                action();
            }
        }
    }
    void clear_stop() { core().clear_stop_request(); }

    /// --update-golden: what the run recorded, written only if every other
    /// step passed (the file's new bytes, or the pose for the step's line).
    struct Golden {
        int line = 0;
        std::optional<fs::path> file;  ///< expect-eeprom: the golden file
        std::string bytes;
        std::optional<plant::Pose> pose;  ///< expect-pose: new x_m, y_m (and theta_rad when given)
    };
    void apply_golden(ScenarioResult& r) {
        if (golden_.empty()) return;
        if (r.verdict != Verdict::kPass) {
            r.message += fmt::format(" (--update-golden: nothing recorded, the run did not pass)");
            return;
        }
        // The scenario file: each pose step's own lines, from its line to the next step's.
        std::string text;
        {
            std::ifstream in(s_.file, std::ios::binary);
            text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        }
        std::vector<std::string> lines;
        for (std::size_t a = 0; a <= text.size();) {
            const std::size_t b = text.find('\n', a);
            lines.push_back(text.substr(a, b == std::string::npos ? std::string::npos : b - a));
            if (b == std::string::npos) break;
            a = b + 1;
        }
        std::vector<std::string> recorded;
        bool yaml_changed = false;
        for (const Golden& g : golden_) {
            if (g.file) {
                write_file_atomic(*g.file, g.bytes);
                recorded.push_back(g.file->filename().string());
                continue;
            }
            int end_line = static_cast<int>(lines.size()) + 1;
            for (const Step& st : s_.steps) {
                if (st.line > g.line) end_line = std::min(end_line, st.line);
            }
            const auto set = [&](const char* key, double value) {
                const std::regex re(std::string("(\\b") + key + ":\\s*)[-+0-9.eE]+");
                for (int l = g.line; l < end_line && l <= static_cast<int>(lines.size()); ++l) {
                    std::string& line = lines[static_cast<std::size_t>(l - 1)];
                    std::smatch m;
                    if (std::regex_search(line, m, re)) {
                        line = m.prefix().str() + m[1].str() + fmt::format("{:.4f}", value) + m.suffix().str();
                        return;
                    }
                }
            };
            set("x_m", g.pose->x_m);
            set("y_m", g.pose->y_m);
            set("theta_rad", g.pose->theta_rad);  // only where the step gives one
            yaml_changed = true;
            recorded.push_back(fmt::format("the pose at line {}", g.line));
        }
        if (yaml_changed) {
            std::string out;
            for (std::size_t l = 0; l < lines.size(); ++l) out += lines[l] + (l + 1 < lines.size() ? "\n" : "");
            write_file_atomic(s_.file, out);
        }
        r.message = fmt::format("--update-golden: recorded {}", fmt::join(recorded, ", "));
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
        const std::string bytes = as_firmware_receives(w.text);
        rig_->uart().send(bytes);
        if (bytes != w.text) return fmt::format("the firmware's receiver made {} byte(s) of it", bytes.size());
        return {};
    }
    /// "received N bytes (M framing errors), ending '...'": the last 60
    /// received characters, escaped (\r, \n shown as such).
    std::string received_tail() const {
        const std::string_view seen = text_.view();
        const std::string tail = seen.size() > 60 ? "..." + std::string(seen.substr(seen.size() - 60)) : std::string(seen);
        return fmt::format("received {} bytes ({} framing errors), ending '{}'", text_.size(), adapter_->framing_errors(),
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
        const std::vector<std::string> warnings = rig_->driver().wiring_warnings();
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
                if (in.used && !in.tied_high && in.pin == pin) return true;
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
        boundary_condition_ = [&] { return pin_level(w.pin) == w.value; };
        const Cycles end = w.timeout == 0 ? kNever : start + w.timeout;
        const bool ok = advance(end, [&] { return pin_level(w.pin) == w.value; });
        boundary_condition_ = nullptr;
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
        std::string note;
        if (e.bin) {
            std::ifstream in(*e.bin, std::ios::binary);
            const std::string want((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            const hil::EepromImage image = rig_->eeprom().read_all();
            if (want.size() != image.size()) {
                throw StepFailed{Verdict::kFail, fmt::format("{} has {} bytes, the EEPROM {}", e.bin->string(), want.size(), image.size())};
            }
            for (std::size_t a = 0; a < image.size(); ++a) {
                if (static_cast<uint8_t>(want[a]) != image[a]) {
                    throw StepFailed{Verdict::kFail, fmt::format("EEPROM byte 0x{:03x}: expected 0x{:02x}, got 0x{:02x}", a,
                                                                 static_cast<uint8_t>(want[a]), image[a])};
                }
            }
            note = fmt::format("{} bytes equal", image.size());
        }
        if (e.log) {
            const auto log = eeprom_log();
            Table want;
            try {
                want = read_table(*e.log);
            } catch (const std::exception& ex) {
                throw StepFailed{Verdict::kFail, ex.what()};
            }
            const auto& wx = want.col("x_m", *e.log);
            const auto& wy = want.col("y_m", *e.log);
            const std::size_t k = want.rows();
            if (k != log.size()) {
                throw StepFailed{Verdict::kFail, fmt::format("the EEPROM log has {} samples, {} has {}", log.size(),
                                                             e.log->filename().string(), k)};
            }
            double worst = 0.0;
            for (std::size_t i = 0; i < k; ++i) {
                const double d = std::hypot(log[i].x_m - wx[i], log[i].y_m - wy[i]);
                worst = std::max(worst, d);
                if (d > e.tol_m) {
                    throw StepFailed{Verdict::kFail, fmt::format("EEPROM log sample {}: ({:.3f}, {:.3f}) is {:.4f} m from "
                                                                 "({:.3f}, {:.3f}) in {}, tolerance {} m",
                                                                 i + 1, log[i].x_m, log[i].y_m, d, wx[i], wy[i],
                                                                 e.log->filename().string(), e.tol_m)};
                }
            }
            note += fmt::format("{}{} samples within {:.4f} m", note.empty() ? "" : "; ", k, worst);
        }
        return note;
    }
    std::string run_step(const ExpectCompare& e) {
        const auto log = eeprom_log();
        if (log.empty()) throw StepFailed{Verdict::kFail, "the EEPROM log is empty: nothing to compare"};
        namespace hs = ddmr::hostsim;
        hs::SimConfig c = hs::config_for_case(e.test_case, hs::Model::firmware);
        c.plant = s_.plant;
        c.pwm = s_.pwm == plant::DriveMode::switched ? hs::PwmModel::switched : hs::PwmModel::averaged;
        c.fidelity = hs::Fidelity::all();
        c.duration_s = std::max(c.duration_s, static_cast<double>(kIterationsPerLogSample * log.size()) * c.period_s + 0.05);
        hs::validate(c);
        const hs::SimResult sim = hs::simulate(c);
        std::vector<Point2> logged;
        logged.reserve(log.size());
        for (const auto& p : log) logged.push_back({p.x_m, p.y_m});
        const PairMetrics m = compare_tracks(logged, sim_track(sim, c, logged.size()));
        if (m.rms_m > e.max_rms_m || (e.max_endpoint_m && m.endpoint_m > *e.max_endpoint_m)) {
            throw StepFailed{Verdict::kFail,
                             fmt::format("EEPROM log vs host simulation (case {}): rms {:.4f} m (max {}), endpoint {:.4f} m{}",
                                         e.test_case, m.rms_m, e.max_rms_m, m.endpoint_m,
                                         e.max_endpoint_m ? fmt::format(" (max {})", *e.max_endpoint_m) : "")};
        }
        return fmt::format("rms {:.4f} m, endpoint {:.4f} m over {} samples", m.rms_m, m.endpoint_m, m.samples);
    }
    std::string run_step(const ExpectLoop& e) {
        if (!e.include_eeprom_writes && !rig_->eeprom_timing().all_writes_recorded()) {
            throw StepFailed{Verdict::kFail,
                             fmt::format("include_eeprom_writes: false needs every EEPROM write, but only the first {} "
                                         "of {} are recorded",
                                         rig_->eeprom_timing().writes().size(), rig_->eeprom_timing().write_count())};
        }
        std::vector<Cycles> write_cycles;
        for (const auto& w : rig_->eeprom_timing().writes()) write_cycles.push_back(w.cycle);
        profiler_->tag_eeprom_writes(write_cycles);
        std::vector<Cycles> compute, period;
        for (const auto& it : profiler_->iterations()) {
            if (!e.include_eeprom_writes && it.eeprom_write) continue;
            compute.push_back(it.compute());
            period.push_back(it.period());
        }
        if (compute.empty()) throw StepFailed{Verdict::kFail, "no complete control-loop iteration was seen"};
        const auto c = hil::cycle_distribution(compute);
        const auto p = hil::cycle_distribution(period);
        const std::vector<std::tuple<const char*, const Range*, double>> checks = {
            {"max_us", &e.max_us, us(c.max)},          {"p99_us", &e.p99_us, us(c.p99)},
            {"mean_us", &e.mean_us, us(c.mean)},
            {"period_max_us", &e.period_max_us, us(p.max)}, {"period_p99_us", &e.period_p99_us, us(p.p99)},
            {"period_mean_us", &e.period_mean_us, us(p.mean)},
        };
        for (const auto& [name, range, value] : checks) {
            if (range->set() && !range->contains(value)) {
                throw StepFailed{Verdict::kFail, fmt::format("expected {} in [{}, {}], got {:.1f} ({} iterations)", name,
                                                             range->min ? fmt::format("{}", *range->min) : "-",
                                                             range->max ? fmt::format("{}", *range->max) : "-", value,
                                                             c.count)};
            }
        }
        return fmt::format("{} iterations: compute max {:.1f} p99 {:.1f} mean {:.1f} us; period max {:.1f} p99 {:.1f} mean {:.1f} us",
                           c.count, us(c.max), us(c.p99), us(c.mean), us(p.max),
                           us(p.p99), us(p.mean));
    }
    std::string run_step(const ExpectIsr& e) {
        const hil::IsrSummary s = isr_->summary();
        for (const auto& v : s.vectors) {
            if (v.name != e.vector) continue;
            if (e.min_count && v.count < *e.min_count) {
                throw StepFailed{Verdict::kFail, fmt::format("expected {} to run at least {} times, it ran {}", e.vector, *e.min_count, v.count)};
            }
            if (e.max_latency_cycles && v.latency.max > *e.max_latency_cycles) {
                throw StepFailed{Verdict::kFail, fmt::format("expected {} entry latency <= {} cycles, worst {} cycles",
                                                             e.vector, *e.max_latency_cycles, v.latency.max)};
            }
            if (e.max_duration_cycles && v.duration.max > *e.max_duration_cycles) {
                throw StepFailed{Verdict::kFail, fmt::format("expected {} duration <= {} cycles, longest {} cycles",
                                                             e.vector, *e.max_duration_cycles, v.duration.max)};
            }
            return fmt::format("{}: {} entries, latency max {} cycles, duration max {} cycles", v.name, v.count,
                               v.latency.max, v.duration.max);
        }
        if (e.min_count && *e.min_count == 0) return fmt::format("{} never ran", e.vector);
        throw StepFailed{Verdict::kFail, fmt::format("interrupt {} never ran", e.vector)};
    }
    std::string run_step(const ExpectNoTornReads& e) {
        std::string note;
        uint64_t observed = 0;
        for (const hil::SplitAccess& a : races_->splits()) {
            if (!races_->is_race(a)) continue;
            const std::string& name = races_->objects()[a.object].name;
            if (!e.variables.empty() && std::find(e.variables.begin(), e.variables.end(), name) == e.variables.end()) {
                continue;
            }
            if (a.observed == 0) continue;
            observed += a.observed;
            note += fmt::format("{}{} {} of {} at 0x{:04x} ({}x)", note.empty() ? "" : "; ",
                                a.kind == hil::AccessKind::kRead ? "read" : "write", "torn", name, a.pc, a.observed);
        }
        if (observed > 0) throw StepFailed{Verdict::kFail, "torn values observed: " + note + " (isr.md lists them)"};
        const nlohmann::json counts = torn_reads_summary(*races_);
        std::string seen;
        for (const auto& [name, c] : counts.items()) {
            if (!e.variables.empty() && std::find(e.variables.begin(), e.variables.end(), name) == e.variables.end()) {
                continue;
            }
            seen += fmt::format("{}{}: {} reads split by a writing ISR, {} changed mid-read", seen.empty() ? "" : "; ",
                                name, c["split_reads"].get<uint64_t>(), c["torn"].get<uint64_t>());
        }
        return fmt::format("no torn value observed ({} interrupt entries checked){}{}",
                           races_->stats().entries_checked, seen.empty() ? "" : ": ", seen);
    }
    std::string run_step(const ExpectEncoders& e) {
        uint64_t lost = 0;
        for (unsigned ch = 0; ch < 2; ++ch) lost += rig_->encoders().stats(ch).lost_edges;
        if (lost > e.max_lost) throw StepFailed{Verdict::kFail, fmt::format("expected at most {} lost encoder edges, {} were lost", e.max_lost, lost)};
        return fmt::format("{} edges lost", lost);
    }
    /// A plant signal now, as truth.csv would write it.
    double signal_now(const std::string& name) {
        return plant_signal(hil::truth_sample_of(rig_->robot(), core().cycle()), name);
    }
    std::string run_step(const WaitUntil& w) {
        const Cycles start = core().cycle();
        const auto met = [&] { return holds(signal_now(w.signal), w.op, w.value); };
        boundary_condition_ = met;
        const Cycles end = w.timeout == 0 ? kNever : start + w.timeout;
        bool ok = false;
        try {
            ok = advance(end, met);
        } catch (StepFailed& f) {  // the scenario's timeout or a firmware failure: say what the signal was
            boundary_condition_ = nullptr;
            f.message += fmt::format("; {} was {:.9g}", w.signal, signal_now(w.signal));
            throw;
        }
        boundary_condition_ = nullptr;
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
    void set_faults(const std::function<void(plant::RobotFaults&)>& change) {
        plant::RobotFaults f = rig_->robot().faults();
        change(f);
        rig_->robot().set_faults(f);
    }
    std::string run_step(const InjectDrop& d) {
        const auto m = static_cast<std::size_t>(d.encoder - 1);
        rig_->robot().set_missed_edge_probability(m, d.drop);
        if (d.duration) at(core().cycle() + *d.duration, [this, m] { rig_->robot().set_missed_edge_probability(m, 0.0); });
        return {};
    }
    std::string run_step(const Stall& st) {
        const auto m = static_cast<std::size_t>(st.motor - 1);
        set_faults([m](plant::RobotFaults& f) { f.shaft_locked[m] = true; });
        at(core().cycle() + st.duration, [this, m] { set_faults([m](plant::RobotFaults& f) { f.shaft_locked[m] = false; }); });
        return {};
    }
    std::string run_step(const Battery& b) {
        set_faults([&](plant::RobotFaults& f) { f.source_V = b.volts; });
        if (b.duration) at(core().cycle() + *b.duration, [this] { set_faults([](plant::RobotFaults& f) { f.source_V.reset(); }); });
        return {};
    }
    std::string run_step(const Slip& sl) {
        const auto m = static_cast<std::size_t>(sl.wheel - 1);
        set_faults([&](plant::RobotFaults& f) { f.traction[m] = sl.traction; });
        if (sl.duration) at(core().cycle() + *sl.duration, [this, m] { set_faults([m](plant::RobotFaults& f) { f.traction[m] = 1.0; }); });
        return {};
    }
    std::string run_step(const Push& p) {
        rig_->robot().displace(plant::Pose{p.dx_m, p.dy_m, p.dtheta_rad});
        return {};
    }
    std::string run_step(const Reset&) {
        core().reset();  // parts re-arm through their reset listeners; EEPROM and plant keep their state
        return fmt::format("reset #{}", core().resets());
    }

    static std::string printable(const std::string& s) {
        std::string out;
        for (const char c : s) {
            const auto u = static_cast<unsigned char>(c);
            if (c == '\n') out += "\\n";
            else if (c == '\r') out += "\\r";
            else if (u < 0x20 || u >= 0x7F) out += fmt::format("\\x{:02x}", u);
            else out.push_back(c);
        }
        return out;
    }

    void write_artifacts(const ScenarioResult& r) {
        json steps = json::array();
        for (const auto& o : r.steps) {
            steps.push_back({{"line", o.line}, {"kind", o.kind}, {"step", o.text}, {"passed", o.passed},
                             {"cycle", o.cycle}, {"t_s", seconds(o.cycle)}, {"message", o.message}});
        }
        const json result = {
            {"name", r.name},
            {"file", r.file.string()},
            {"firmware", s_.firmware.string()},
            {"sketch", s_.sketch_build ? [&] {
                 // Built (or found) before the suite ran: whether this worker found it cached says nothing.
                 json j = sketch_build_json(*s_.sketch_build);
                 j.erase("from_cache");
                 return j;
             }()
                                       : json(nullptr)},
            {"platformio", s_.firmware_source},
            {"seed", s_.seed},
            {"baud", s_.baud},
            {"verdict", to_string(r.verdict)},
            {"exit_code", exit_code(r.verdict)},
            {"message", r.message},
            {"cycles", r.cycles},
            {"clock_hz", r.clock_hz},
            {"sim_seconds", r.sim_seconds},
            {"steps", steps},
            {"steps_total", s_.steps.size()},
            {"uart_bytes", r.uart_bytes},
            {"framing_errors", r.framing_errors},
            {"board", s_.board_file ? json(s_.board_file->string()) : json(nullptr)},
            {"wiring_warnings", rig_->driver().wiring_warnings()},
        };
        const hil::EepromImage image = rig_->eeprom().read_all();
        uart_txt_->commit();
        write_file_atomic(out_dir_ / "eeprom.bin",
                          std::string_view(reinterpret_cast<const char*>(image.data()), image.size()));
        const RaceReport race = race_report(*races_, elf_);
        write_file_atomic(out_dir_ / "isr.md", hil::to_markdown(isr_->summary()) + race.markdown);
        write_file_atomic(out_dir_ / "eeprom_log.csv", hil::eeprom_log_csv(eeprom_log()));
        // wall time is not deterministic: it goes to stdout, not into result.json
        if (r.verdict != Verdict::kPass) {
            vcd_->finish();
            write_file_atomic(out_dir_ / "failure_window.vcd", vcd_text_);
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
    std::optional<hil::EepromImage> preload_;
    std::optional<hil::RobotRig> rig_;
    std::optional<hil::IsrMonitor> isr_;
    std::optional<hil::StackGuard> stack_guard_;
    std::optional<hil::RaceDetector> races_;
    std::optional<hil::LoopProfiler> profiler_;
    std::string vcd_text_;
    std::optional<hil::VcdWriter> vcd_writer_;
    std::optional<hil::VcdRecorder> vcd_;
    bool armed_ = false;
    std::optional<hil::HostAdapter> adapter_;  ///< the host's serial adapter at the scenario's baud
    std::vector<hil::LineByte> scratch_;
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
    std::function<bool()> boundary_condition_;
    std::vector<std::pair<Cycles, std::function<void()>>> timed_;
    Cycles origin_cycle_ = 0;  ///< the first write-serial: the EEPROM log's time origin
};

}  // namespace

void check_firmware_names(const Scenario& s) {
    const auto elf = hil::ElfImage::read(s.firmware);
    const hil::DataObjects objects(elf, *hil::board_description(s.board.model).mcu);
    const hil::McuDescription& mcu = *hil::board_description(s.board.model).mcu;
    // expect-var: a variable in SRAM whose size the type (given, or by size) matches.
    for (const Step& step : s.steps) {
        const auto* e = std::get_if<ExpectVar>(&step.action);
        if (e == nullptr) continue;
        const std::string where = fmt::format("{}:{}: expect-var: ", s.file.string(), step.line);
        const auto sym = elf.find(e->name);
        if (!sym) {
            throw std::invalid_argument(where + fmt::format("the firmware has no symbol '{}' (not a global, or folded "
                                                            "away by LTO)",
                                                            e->name));
        }
        if (!sym->is_object || sym->address < mcu.sram_start || sym->address + sym->size - 1 > mcu.ram_end) {
            throw std::invalid_argument(where + fmt::format("'{}' is not a variable in SRAM", e->name));
        }
        if (!e->type) {
            if (!hil::default_var_type(sym->size, hil::FourByteDefault::kNone)) {
                throw std::invalid_argument(where + fmt::format("'{}' has {} bytes: give its type (type: int32, uint32 or "
                                                                "float)",
                                                                e->name, sym->size));
            }
        } else if (hil::var_type_size(*e->type) != sym->size) {
            throw std::invalid_argument(where + fmt::format("'{}' is {} bytes; {} is {}", e->name, sym->size,
                                                            hil::to_string(*e->type), hil::var_type_size(*e->type)));
        }
    }
    // Variables named by expect-no-torn-reads must be multi-byte variables in SRAM.
    for (const Step& step : s.steps) {
        const auto* e = std::get_if<ExpectNoTornReads>(&step.action);
        if (e == nullptr) continue;
        for (const std::string& name : e->variables) {
            const auto o = objects.find(name);
            if (!o) {
                throw std::invalid_argument(fmt::format("{}:{}: expect-no-torn-reads: the firmware has no variable '{}' in SRAM",
                                                        s.file.string(), step.line, name));
            }
            const uint16_t size = objects[*o].size;
            if (size < 2 || size > hil::RaceDetector::kMaxVariableBytes) {
                throw std::invalid_argument(fmt::format("{}:{}: expect-no-torn-reads: '{}' has {} byte(s); a torn access needs 2..{}",
                                                        s.file.string(), step.line, name, size,
                                                        hil::RaceDetector::kMaxVariableBytes));
            }
        }
    }
}

ScenarioResult run_scenario(const Scenario& s, const fs::path& out_dir, bool progress, bool update_golden) {
    Session session(s, out_dir, progress, update_golden);
    return session.run();
}

}  // namespace ddmr::tools::scenario
