#include "scenario/scenario_yaml.hpp"
#include "scenario/step_catalog.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <regex>
#include <set>
#include <sstream>

#include "common/arduino_libraries.hpp"
#include "common/platformio_project.hpp"
#include "hil/board.hpp"
#include "hil/plant_coupler.hpp"
#include "plant/params_yaml.hpp"

namespace ddmr::tools::scenario {
namespace fs = std::filesystem;

const char* to_string(CompareOp op) {
    switch (op) {
        case CompareOp::kEq: return "==";
        case CompareOp::kNe: return "!=";
        case CompareOp::kLt: return "<";
        case CompareOp::kLe: return "<=";
        case CompareOp::kGt: return ">";
        case CompareOp::kGe: return ">=";
    }
    return "?";
}

bool holds(double lhs, CompareOp op, double rhs) {
    switch (op) {
        case CompareOp::kEq: return lhs == rhs;
        case CompareOp::kNe: return lhs != rhs;
        case CompareOp::kLt: return lhs < rhs;
        case CompareOp::kLe: return lhs <= rhs;
        case CompareOp::kGt: return lhs > rhs;
        case CompareOp::kGe: return lhs >= rhs;
    }
    return false;
}

namespace {

/// A plant signal: its name and how to read it from a truth sample.
struct SignalDef {
    std::string_view name;
    double (*get)(const hil::TruthSample&);
};

double level(bool b) { return b ? 1.0 : 0.0; }

// truth.csv's columns (tools/common/truth_csv.cpp) but t_s, then the wheel
// aliases: right = index 0 = motor 1, left = index 1 = motor 2 (hil::wheel_name).
constexpr std::array kSignals{
    SignalDef{"x_m", [](const hil::TruthSample& t) { return t.x_m; }},
    SignalDef{"y_m", [](const hil::TruthSample& t) { return t.y_m; }},
    SignalDef{"theta_rad", [](const hil::TruthSample& t) { return t.theta_rad; }},
    SignalDef{"v_m_s", [](const hil::TruthSample& t) { return t.v_m_s; }},
    SignalDef{"omega_rad_s", [](const hil::TruthSample& t) { return t.omega_rad_s; }},
    SignalDef{"ia1_A", [](const hil::TruthSample& t) { return t.ia1_A; }},
    SignalDef{"ia2_A", [](const hil::TruthSample& t) { return t.ia2_A; }},
    SignalDef{"wheel1_rad_s", [](const hil::TruthSample& t) { return t.wheel1_rad_s; }},
    SignalDef{"wheel2_rad_s", [](const hil::TruthSample& t) { return t.wheel2_rad_s; }},
    SignalDef{"vbatt_V", [](const hil::TruthSample& t) { return t.vbatt_V; }},
    SignalDef{"edges1", [](const hil::TruthSample& t) { return static_cast<double>(t.edges1); }},
    SignalDef{"edges2", [](const hil::TruthSample& t) { return static_cast<double>(t.edges2); }},
    SignalDef{"duty1", [](const hil::TruthSample& t) { return t.duty1; }},
    SignalDef{"duty2", [](const hil::TruthSample& t) { return t.duty2; }},
    SignalDef{"dir1", [](const hil::TruthSample& t) { return level(t.dir1); }},
    SignalDef{"dir2", [](const hil::TruthSample& t) { return level(t.dir2); }},
    SignalDef{"right.wheel_rad_s", [](const hil::TruthSample& t) { return t.wheel1_rad_s; }},
    SignalDef{"left.wheel_rad_s", [](const hil::TruthSample& t) { return t.wheel2_rad_s; }},
    SignalDef{"right.current_A", [](const hil::TruthSample& t) { return t.ia1_A; }},
    SignalDef{"left.current_A", [](const hil::TruthSample& t) { return t.ia2_A; }},
    SignalDef{"right.edges", [](const hil::TruthSample& t) { return static_cast<double>(t.edges1); }},
    SignalDef{"left.edges", [](const hil::TruthSample& t) { return static_cast<double>(t.edges2); }},
    SignalDef{"right.duty", [](const hil::TruthSample& t) { return t.duty1; }},
    SignalDef{"left.duty", [](const hil::TruthSample& t) { return t.duty2; }},
};

const SignalDef* find_signal(std::string_view name) {
    for (const SignalDef& d : kSignals) {
        if (d.name == name) return &d;
    }
    return nullptr;
}

}  // namespace

const std::vector<std::string>& plant_signal_names() {
    static const std::vector<std::string> names = [] {
        std::vector<std::string> v;
        v.reserve(kSignals.size());
        for (const SignalDef& d : kSignals) v.emplace_back(d.name);
        return v;
    }();
    return names;
}

bool is_plant_signal(std::string_view name) { return find_signal(name) != nullptr; }

double plant_signal(const hil::TruthSample& t, std::string_view name) {
    const SignalDef* d = find_signal(name);
    if (d == nullptr) throw std::invalid_argument(fmt::format("'{}' is not a plant signal", name));
    return d->get(t);
}

bool Scenario::needs_loop_profile() const {
    return std::any_of(steps.begin(), steps.end(),
                       [](const Step& s) { return std::holds_alternative<ExpectLoop>(s.action); });
}

Cycles parse_duration(std::string_view text, uint32_t clock_hz) {
    const std::string s(text);
    static const std::regex re(R"(^\s*([0-9]+(?:\.[0-9]*)?(?:[eE][+-]?[0-9]+)?)\s*(s|ms|us|cycles)\s*$)");
    std::smatch m;
    if (!std::regex_match(s, m, re)) {
        throw std::invalid_argument(fmt::format(
            "duration '{}': expected a non-negative number with a unit (s, ms, us or cycles), e.g. 500ms", s));
    }
    double value = 0.0;
    try {
        value = std::stod(m[1].str());
    } catch (const std::out_of_range&) {
        throw std::invalid_argument(fmt::format("duration '{}': too large", s));
    }
    const std::string unit = m[2].str();
    const double scale = unit == "s" ? clock_hz : unit == "ms" ? clock_hz / 1e3 : unit == "us" ? clock_hz / 1e6 : 1.0;
    const double cycles = std::round(value * scale);
    if (!std::isfinite(cycles) || cycles > 1e15) {
        throw std::invalid_argument(fmt::format("duration '{}': too large", s));
    }
    return static_cast<Cycles>(cycles);
}

namespace {

/// The YAML node of one key with its location, for messages.
class Ctx {
public:
    /// `board`: the scenario's board (its clock turns durations into cycles, its pins are the valid ones);
    /// `wiring`: the robot wired to it (its motor driver inputs), once known.
    Ctx(const fs::path& file, const YAML::Node& node, std::string key, const hil::BoardDescription& board,
        const hil::BoardWiring* wiring = nullptr)
        : file_(file), node_(node), key_(std::move(key)), board_(&board), wiring_(wiring) {}
    /// Another node of the same file, board and wiring.
    Ctx at(const YAML::Node& node, std::string key) const {
        return Ctx(file_, node, std::move(key), *board_, wiring_);
    }
    const hil::BoardDescription& board() const { return *board_; }
    const hil::BoardWiring* wiring() const { return wiring_; }
    [[noreturn]] void fail(const std::string& what) const {
        throw ScenarioError(fmt::format("{}:{}: key '{}': {}", file_.string(), line(), key_, what));
    }
    int line() const { return node_.Mark().line + 1; }
    const YAML::Node& node() const { return node_; }
    const std::string& key() const { return key_; }
    const fs::path& file() const { return file_; }

    Ctx child(const std::string& key) const { return at(node_[key], key_ + "." + key); }

    std::string str() const {
        if (!node_.IsScalar()) fail("expected a string");
        return node_.Scalar();
    }
    double number() const {
        if (!node_.IsScalar()) fail("expected a number");
        double v = 0.0;
        try {
            std::size_t used = 0;
            v = std::stod(node_.Scalar(), &used);
            if (used != node_.Scalar().size()) throw std::invalid_argument("trailing text");
        } catch (const std::exception&) {
            fail(fmt::format("'{}' is not a number", node_.Scalar()));
        }
        if (!std::isfinite(v)) fail(fmt::format("'{}' is not a finite number", node_.Scalar()));
        return v;
    }
    double number_in(double lo, double hi, const char* range) const {
        const double v = number();
        if (!(v >= lo && v <= hi)) fail(fmt::format("{} is out of range {}", node_.Scalar(), range));
        return v;
    }
    int integer_in(int lo, int hi) const {
        const double v = number();
        if (v != std::floor(v) || v < lo || v > hi) {
            fail(fmt::format("{} is not an integer in [{}, {}]", node_.Scalar(), lo, hi));
        }
        return static_cast<int>(v);
    }
    uint64_t count() const {
        const double v = number();
        if (v != std::floor(v) || v < 0 || v > 9.007e15) fail(fmt::format("{} is not a non-negative integer", node_.Scalar()));
        return static_cast<uint64_t>(v);
    }
    bool boolean() const {
        if (!node_.IsScalar()) fail("expected true/false or 1/0");
        const std::string& s = node_.Scalar();
        if (s == "true" || s == "1" || s == "high" || s == "HIGH") return true;
        if (s == "false" || s == "0" || s == "low" || s == "LOW") return false;
        fail(fmt::format("'{}' is not a level (1/0, true/false, high/low)", s));
    }
    Cycles duration() const {
        try {
            return parse_duration(str(), board_->clock_hz);
        } catch (const std::invalid_argument& e) {
            fail(e.what());
        }
    }
    /// Refuses keys outside `allowed`; requires those in `required`.
    void keys(std::initializer_list<const char*> allowed, std::initializer_list<const char*> required = {}) const {
        if (!node_.IsMap()) fail("expected a mapping of keys");
        for (const auto& kv : node_) {
            const std::string k = kv.first.Scalar();
            if (std::none_of(allowed.begin(), allowed.end(), [&](const char* a) { return k == a; })) {
                std::string list;
                for (const char* a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
                at(kv.first, key_ + "." + k).fail(fmt::format("unknown key (allowed: {})", list));
            }
        }
        for (const char* r : required) {
            if (!node_[r]) fail(fmt::format("missing required key '{}'", r));
        }
    }
    bool has(const char* k) const { return static_cast<bool>(node_[k]); }

private:
    fs::path file_;
    YAML::Node node_;
    std::string key_;
    const hil::BoardDescription* board_;
    const hil::BoardWiring* wiring_;
};

/// A path written in the scenario: relative, inside the scenario's folder.
fs::path inside_folder(const Ctx& c) {
    const std::string text = c.str();
    const fs::path p(text);
    if (p.is_absolute()) {
        c.fail(fmt::format("'{}' is absolute: paths in a scenario are relative to its folder "
                           "(give other files on the command line)", text));
    }
    const fs::path folder = fs::absolute(c.file()).parent_path().lexically_normal();
    fs::path full = (folder / p).lexically_normal();  // not const: returned by move
    const auto rel = full.lexically_relative(folder);
    if (rel.empty() || *rel.begin() == "..") {
        c.fail(fmt::format("'{}' leaves the scenario's folder {}", text, folder.string()));
    }
    return full;
}

fs::path existing_file(const Ctx& c) {
    fs::path p = inside_folder(c);
    if (!fs::is_regular_file(p)) c.fail(fmt::format("file '{}' does not exist", p.string()));
    return p;
}

/// A digital pin of the scenario's board: its number, or its silkscreen name
/// as a board file takes it ("D22", "A8").
int board_pin(const Ctx& c) {
    const std::string text = c.str();
    if (!text.empty() && std::isdigit(static_cast<unsigned char>(text.front())) != 0) {
        return c.integer_in(0, c.board().pin_count() - 1);
    }
    const std::optional<int> pin = hil::parse_pin_name(c.board(), text);
    if (!pin) c.fail(fmt::format("'{}' is not a pin of the {} (pins {})", text, c.board().label, hil::pin_range(c.board())));
    return *pin;
}

/// A timer-output pin that drives a motor driver input of the wiring.
int pwm_pin(const Ctx& c) {
    const int pin = board_pin(c);
    if (!hil::board_pin(c.board(), pin)->oc) {
        c.fail(fmt::format("pin {} has no timer output (PWM pins: {})", pin, hil::pwm_pin_list(c.board())));
    }
    if (c.wiring() != nullptr) {
        std::vector<int> inputs;  // the wiring's driver inputs on timer pins
        for (const hil::WheelWiring& w : c.wiring()->wheel) {
            for (const hil::InputWire& in : w.motor.input) {
                if (in.used && !in.tied_high && hil::board_pin(c.board(), in.pin)->oc &&
                    std::find(inputs.begin(), inputs.end(), in.pin) == inputs.end()) {
                    inputs.push_back(in.pin);
                }
            }
        }
        if (std::find(inputs.begin(), inputs.end(), pin) == inputs.end()) {
            std::sort(inputs.begin(), inputs.end());
            c.fail(fmt::format("pin {} feeds no motor driver input of the board ({}); the driver inputs on timer "
                               "pins are {}",
                               pin, c.wiring()->source,
                               inputs.empty() ? std::string("none") : fmt::format("{}", fmt::join(inputs, ", "))));
        }
    }
    return pin;
}

CompareOp compare_op(const Ctx& c) {
    const std::string s = c.str();
    if (s == "==") return CompareOp::kEq;
    if (s == "!=") return CompareOp::kNe;
    if (s == "<") return CompareOp::kLt;
    if (s == "<=") return CompareOp::kLe;
    if (s == ">") return CompareOp::kGt;
    // cppcheck-suppress missingReturn ; the path ends in Ctx::fail, [[noreturn]] (it throws)
    if (s == ">=") return CompareOp::kGe;
    c.fail(fmt::format("'{}' is not one of ==, !=, <, <=, >, >=", s));
}

void check_regex(const Ctx& c, const std::string& pattern) {
    try {
        std::regex re(pattern, std::regex::ECMAScript);
    } catch (const std::regex_error& e) {
        c.fail(fmt::format("'{}' is not a valid regular expression: {}", pattern, e.what()));
    }
}

/// A wheel: 1 or `right` (motor 1), 2 or `left` (motor 2).
int wheel_number(const Ctx& c) {
    const std::string s = c.str();
    if (s == "right") return 1;
    if (s == "left") return 2;
    char* end = nullptr;
    const double v = std::strtod(s.c_str(), &end);
    // cppcheck-suppress missingReturn ; the path ends in Ctx::fail, [[noreturn]] (it throws)
    if (!s.empty() && end == s.c_str() + s.size() && (v == 1.0 || v == 2.0)) return static_cast<int>(v);
    c.fail(fmt::format("'{}' is not a wheel (1 or right, 2 or left)", s));
}

std::string plant_signal_name(const Ctx& c) {
    std::string s = c.str();
    if (!is_plant_signal(s)) {
        std::string list;
        for (const std::string& n : plant_signal_names()) list += (list.empty() ? "" : ", ") + n;
        c.fail(fmt::format("'{}' is not a plant signal (one of {})", s, list));
    }
    return s;
}

std::optional<Cycles> optional_for(const Ctx& c) {
    if (!c.has("for")) return std::nullopt;
    return c.child("for").duration();
}

StepAction parse_step(const std::string& kind, const Ctx& c) {
    if (find_step(kind) == nullptr) {
        std::string kinds;
        for (const StepInfo& i : step_catalog()) kinds += (kinds.empty() ? "" : ", ") + std::string(i.kind);
        c.fail(fmt::format("unknown step (the steps: {}; `ddmr-hil scenario --list-steps` shows their forms)", kinds));
    }
    if (kind == "delay") return Delay{c.duration()};
    if (kind == "write-serial") return WriteSerial{c.str()};
    if (kind == "wait-serial") {
        if (c.node().IsScalar()) return WaitSerial{c.str(), 0};
        c.keys({"text", "timeout"}, {"text"});
        return WaitSerial{c.child("text").str(), c.has("timeout") ? c.child("timeout").duration() : 0};
    }
    if (kind == "expect-serial" || kind == "fail-serial" || kind == "expect-warning") {
        const std::string pattern = c.str();
        check_regex(c, pattern);
        if (kind == "fail-serial") return FailSerial{pattern};
        if (kind == "expect-warning") return ExpectWarning{pattern};
        return ExpectSerial{pattern};
    }
    if (kind == "wait-pin") {
        c.keys({"pin", "value", "timeout"}, {"pin", "value"});
        return WaitPin{board_pin(c.child("pin")), c.child("value").boolean(),
                       c.has("timeout") ? c.child("timeout").duration() : 0};
    }
    if (kind == "expect-pin") {
        c.keys({"pin", "value"}, {"pin", "value"});
        return ExpectPin{board_pin(c.child("pin")), c.child("value").boolean()};
    }
    if (kind == "expect-pwm") {
        c.keys({"pin", "duty", "tol"}, {"pin", "duty"});
        return ExpectPwm{pwm_pin(c.child("pin")), c.child("duty").number_in(0, 1, "[0, 1]"),
                         c.has("tol") ? c.child("tol").number_in(0, 1, "[0, 1]") : 0.01};
    }
    if (kind == "expect-var") {
        c.keys({"name", "type", "op", "value"}, {"name", "value"});
        ExpectVar v;
        v.name = c.child("name").str();
        if (c.has("type")) {
            try {
                v.type = hil::parse_var_type(c.child("type").str());
            } catch (const std::invalid_argument& e) {
                c.child("type").fail(e.what());
            }
        }
        if (c.has("op")) v.op = compare_op(c.child("op"));
        v.value = c.child("value").number();
        return v;
    }
    if (kind == "expect-pose") {
        c.keys({"source", "x_m", "y_m", "tol_m", "theta_rad", "tol_rad"}, {"x_m", "y_m", "tol_m"});
        ExpectPose p;
        if (c.has("source")) {
            const std::string s = c.child("source").str();
            if (s == "truth") p.source = PoseSource::kTruth;
            else if (s == "firmware") p.source = PoseSource::kFirmware;
            else c.child("source").fail(fmt::format("'{}' is not truth or firmware", s));
        }
        p.x_m = c.child("x_m").number();
        p.y_m = c.child("y_m").number();
        p.tol_m = c.child("tol_m").number_in(0, 100, "[0, 100] m");
        if (c.has("theta_rad")) {
            p.theta_rad = c.child("theta_rad").number();
            if (!c.has("tol_rad")) c.fail("theta_rad needs tol_rad");
            p.tol_rad = c.child("tol_rad").number_in(0, 100, "[0, 100] rad");
        }
        return p;
    }
    if (kind == "expect-eeprom") {
        c.keys({"bin", "log", "tol_m"});
        ExpectEeprom e;
        if (c.has("bin")) e.bin = existing_file(c.child("bin"));
        if (c.has("log")) {
            e.log = existing_file(c.child("log"));
            if (!c.has("tol_m")) c.fail("log needs tol_m");
            e.tol_m = c.child("tol_m").number_in(0, 100, "[0, 100] m");
        }
        if (!e.bin && !e.log) c.fail("give bin (the raw EEPROM, every byte) or log (CSV) with tol_m");
        return e;
    }
    if (kind == "expect-compare") {
        c.keys({"case", "max_rms_m", "max_endpoint_m"}, {"max_rms_m"});
        ExpectCompare e;
        if (c.has("case")) e.test_case = c.child("case").integer_in(1, 2);
        e.max_rms_m = c.child("max_rms_m").number_in(0, 100, "[0, 100] m");
        if (c.has("max_endpoint_m")) e.max_endpoint_m = c.child("max_endpoint_m").number_in(0, 100, "[0, 100] m");
        return e;
    }
    if (kind == "expect-loop") {
        c.keys({"max_us", "p99_us", "mean_us", "period_max_us", "period_p99_us", "period_mean_us",
                "include_eeprom_writes"});
        ExpectLoop l;
        const auto range = [&](const char* k, Range& out) {
            if (!c.has(k)) return;
            const Ctx r = c.child(k);
            if (r.node().IsSequence()) {
                if (r.node().size() != 2) r.fail("expected a bound or [min, max]");
                out.min = r.at(r.node()[0], r.key() + "[0]").number_in(0, 1e9, "[0, 1e9] us");
                out.max = r.at(r.node()[1], r.key() + "[1]").number_in(0, 1e9, "[0, 1e9] us");
                if (*out.min > *out.max) r.fail("min is above max");
            } else {
                out.max = r.number_in(0, 1e9, "[0, 1e9] us");
            }
        };
        range("max_us", l.max_us);
        range("p99_us", l.p99_us);
        range("mean_us", l.mean_us);
        range("period_max_us", l.period_max_us);
        range("period_p99_us", l.period_p99_us);
        range("period_mean_us", l.period_mean_us);
        if (c.has("include_eeprom_writes")) l.include_eeprom_writes = c.child("include_eeprom_writes").boolean();
        if (!l.max_us.set() && !l.p99_us.set() && !l.mean_us.set() && !l.period_max_us.set() &&
            !l.period_p99_us.set() && !l.period_mean_us.set()) {
            c.fail("give at least one bound (max_us, p99_us, mean_us, period_max_us, period_p99_us, period_mean_us)");
        }
        return l;
    }
    if (kind == "expect-isr") {
        c.keys({"vector", "max_latency_cycles", "max_duration_cycles", "min_count"}, {"vector"});
        ExpectIsr e;
        e.vector = c.child("vector").str();
        const std::vector<const char*>& names = c.board().mcu->vector_names;
        if (e.vector == "RESET" ||
            std::find_if(names.begin(), names.end(), [&](const char* n) { return e.vector == n; }) == names.end()) {
            c.child("vector").fail(fmt::format("'{}' is not an interrupt of the {} (avr-libc's names without _vect: "
                                               "{})",
                                               e.vector, c.board().mcu->label,
                                               fmt::join(names.begin() + 1, names.end(), ", ")));
        }
        if (c.has("max_latency_cycles")) e.max_latency_cycles = c.child("max_latency_cycles").count();
        if (c.has("max_duration_cycles")) e.max_duration_cycles = c.child("max_duration_cycles").count();
        if (c.has("min_count")) e.min_count = c.child("min_count").count();
        return e;
    }
    if (kind == "expect-no-torn-reads") {
        ExpectNoTornReads e;
        if (c.node().IsSequence()) {
            for (std::size_t i = 0; i < c.node().size(); ++i) {
                const YAML::Node v = c.node()[i];
                if (!v.IsScalar() || v.Scalar().empty()) c.fail("expected a list of variable names");
                e.variables.push_back(v.Scalar());
            }
            if (e.variables.empty()) c.fail("expected a list of variable names (or no value: every variable)");
        } else if (!c.node().IsNull() && !(c.node().IsMap() && c.node().size() == 0)) {
            c.fail("takes no value (every variable) or a list of variable names");
        }
        return e;
    }
    if (kind == "expect-encoders") {
        c.keys({"max_lost"}, {"max_lost"});
        return ExpectEncoders{c.child("max_lost").count()};
    }
    if (kind == "wait-until") {
        c.keys({"signal", "op", "value", "timeout"}, {"signal", "value"});
        WaitUntil w;
        w.signal = plant_signal_name(c.child("signal"));
        if (c.has("op")) w.op = compare_op(c.child("op"));
        w.value = c.child("value").number();
        if (c.has("timeout")) w.timeout = c.child("timeout").duration();
        return w;
    }
    if (kind == "expect") {
        c.keys({"signal", "op", "value", "between"}, {"signal"});
        ExpectSignal e;
        e.signal = plant_signal_name(c.child("signal"));
        if (c.has("between")) {
            if (c.has("op") || c.has("value")) c.fail("give op and value, or between: [min, max], not both");
            const Ctx b = c.child("between");
            if (!b.node().IsSequence() || b.node().size() != 2) b.fail("expected [min, max]");
            e.between.min = b.at(b.node()[0], b.key() + "[0]").number();
            e.between.max = b.at(b.node()[1], b.key() + "[1]").number();
            if (*e.between.min > *e.between.max) {
                b.fail(fmt::format("min {} is above max {}", *e.between.min, *e.between.max));
            }
            return e;
        }
        if (!c.has("value")) c.fail("missing required key 'value' (or give between: [min, max])");
        if (c.has("op")) e.op = compare_op(c.child("op"));
        e.value = c.child("value").number();
        return e;
    }
    if (kind == "inject") {
        c.keys({"encoder", "drop", "for"}, {"encoder", "drop"});
        return InjectDrop{wheel_number(c.child("encoder")), c.child("drop").number_in(0, 0.5, "[0, 0.5]"),
                          optional_for(c)};
    }
    if (kind == "stall") {
        c.keys({"motor", "for"}, {"motor", "for"});
        return Stall{wheel_number(c.child("motor")), c.child("for").duration()};
    }
    if (kind == "battery") {
        c.keys({"volts", "for"}, {"volts"});
        return Battery{c.child("volts").number_in(0.1, 50, "[0.1, 50] V"), optional_for(c)};
    }
    if (kind == "slip") {
        c.keys({"wheel", "traction", "for"}, {"wheel", "traction"});
        return Slip{wheel_number(c.child("wheel")), c.child("traction").number_in(0, 1, "[0, 1]"),
                    optional_for(c)};
    }
    if (kind == "push") {
        c.keys({"dx_m", "dy_m", "dtheta_rad"});
        Push p;
        if (c.has("dx_m")) p.dx_m = c.child("dx_m").number_in(-10, 10, "[-10, 10] m");
        if (c.has("dy_m")) p.dy_m = c.child("dy_m").number_in(-10, 10, "[-10, 10] m");
        if (c.has("dtheta_rad")) p.dtheta_rad = c.child("dtheta_rad").number_in(-10, 10, "[-10, 10] rad");
        return p;
    }
    if (kind == "reset") {
        if (!c.node().IsNull() && !(c.node().IsMap() && c.node().size() == 0)) c.fail("takes no value");
        return Reset{};
    }
    // A kind in the catalogue that no branch above parses: a programming error.
    throw std::logic_error("scenario step '" + kind + "' is in the catalogue but not parsed");
}

std::string step_text(const YAML::Node& step) {
    YAML::Emitter e;
    e.SetMapFormat(YAML::Flow);
    e.SetSeqFormat(YAML::Flow);
    e << step;
    return e.c_str();
}

/// Merges `over` into `base`, key by key (scalars replace). An encoder's
/// resolution is one of two keys: giving one drops the other from `base`.
void merge(YAML::Node base, const YAML::Node& over) {
    for (const char* key : {"edges_per_motor_rev", "edges_per_wheel_rev"}) {
        const std::string other = std::string(key) == "edges_per_motor_rev" ? "edges_per_wheel_rev" : "edges_per_motor_rev";
        if (over.IsMap() && over[key] && base.IsMap() && base[other]) base.remove(other);
    }
    for (const auto& kv : over) {
        const std::string k = kv.first.Scalar();
        if (kv.second.IsMap() && base[k] && base[k].IsMap()) {
            merge(base[k], kv.second);
        } else {
            base[k] = YAML::Clone(kv.second);
        }
    }
}

}  // namespace

Scenario parse_scenario(std::string_view yaml_text, const fs::path& file, const LoadOptions& options) {
    YAML::Node root;
    try {
        root = YAML::Load(std::string(yaml_text));
    } catch (const YAML::Exception& e) {
        throw ScenarioError(fmt::format("{}:{}: malformed YAML: {}", file.string(), e.mark.line + 1, e.msg));
    }
    if (!root.IsMap()) throw ScenarioError(fmt::format("{}:1: a scenario is a mapping with a 'steps' list", file.string()));
    Scenario s;
    s.file = file;
    // The board first: its clock and pins give meaning to the rest.
    if (root["board"]) {
        s.board_file = existing_file(Ctx(file, root["board"], "board", hil::board_description(s.board.model)));
        try {
            s.board = hil::load_board_file(*s.board_file);  // its messages name its file, line and key
        } catch (const std::runtime_error& e) {
            throw ScenarioError(e.what());
        }
    }
    // A PlatformIO project names its board: read before anything the board gives meaning to.
    std::optional<PlatformioProject> pio;
    if (!options.firmware_override && root["firmware"] && root["firmware"].IsMap() && root["firmware"]["platformio"]) {
        const Ctx c(file, root["firmware"], "firmware", hil::board_description(s.board.model), &s.board);
        c.keys({"platformio", "env"}, {"platformio"});
        const Ctx d = c.child("platformio");
        const fs::path p(d.str());
        if (p.is_absolute()) d.fail(fmt::format("'{}' is absolute: a scenario's paths are relative to its file", p.string()));
        const std::string env = c.has("env") ? c.child("env").str() : std::string();
        try {
            pio = load_platformio_project((fs::absolute(file).parent_path() / p).lexically_normal(), env);
        } catch (const std::invalid_argument& e) {
            d.fail(e.what());
        }
        if (s.board_file && s.board.model != pio->board) {
            d.fail(fmt::format("[env:{}] is for board {} ({}), the board file {} for {}", pio->env, pio->board_id,
                               hil::board_description(pio->board).key, s.board_file->string(),
                               hil::board_description(s.board.model).key));
        }
        s.board.model = pio->board;  // without a board file: the thesis robot's wiring on that board
        s.firmware = pio->elf;
        s.firmware_source = platformio_json(*pio);
    }
    const hil::BoardDescription& board = hil::board_description(s.board.model);
    const Ctx top(file, root, "(top)", board, &s.board);
    top.keys({"name", "description", "version", "author", "firmware", "libraries", "board", "plant", "pwm",
              "eeprom-timing", "seed", "timeout", "serial", "eeprom", "steps"},
             {"steps", "timeout"});
    s.name = root["name"] ? top.at(root["name"], "name").str() : file.stem().string();
    if (root["description"]) s.description = top.at(root["description"], "description").str();
    // Firmware: the command line's, else the file's, else the reference.
    if (options.firmware_override) {
        s.firmware = *options.firmware_override;
    } else if (pio) {
        // read above
    } else if (root["firmware"] && root["firmware"].IsMap()) {
        const Ctx c = top.at(root["firmware"], "firmware");
        c.keys({"elf", "sketch", "platformio", "env"});
        if (c.has("elf") == c.has("sketch")) {
            c.fail("give one of elf (a built ELF), sketch (a .ino to build) or platformio (a project folder)");
        }
        if (c.has("env")) c.child("env").fail("only with platformio: DIR (the environment of a PlatformIO project)");
        if (c.has("elf")) {
            s.firmware = existing_file(c.child("elf"));
        } else {
            const fs::path ino = existing_file(c.child("sketch"));
            if (ino.extension() != ".ino") c.child("sketch").fail(fmt::format("'{}' is not a .ino sketch", ino.string()));
            if (ino.parent_path().filename() != ino.stem()) {
                c.child("sketch").fail(fmt::format("Arduino needs the sketch in a folder of its name ({0}/{0}.ino)",
                                                   ino.stem().string()));
            }
            s.sketch = ino;
        }
    } else if (root["firmware"] && top.at(root["firmware"], "firmware").str() != "reference") {
        s.firmware = existing_file(top.at(root["firmware"], "firmware"));
    } else {
        s.firmware = options.reference_firmware;
    }
    if (root["libraries"]) {
        // Library folders for the sketch: relative to the scenario file (they
        // may be outside its folder: a sketchbook's libraries/ beside it).
        const Ctx c = top.at(root["libraries"], "libraries");
        if (!s.sketch && !options.firmware_override) c.fail("only a scenario that builds a sketch (firmware: {sketch: x/x.ino}) takes libraries");
        if (!c.node().IsSequence()) c.fail("expected a list of folders, like [../libraries]");
        const fs::path folder = fs::absolute(file).parent_path();
        for (std::size_t i = 0; i < c.node().size(); ++i) {
            const Ctx d = top.at(c.node()[i], fmt::format("libraries[{}]", i));
            const fs::path p(d.str());
            if (p.is_absolute()) {
                d.fail(fmt::format("'{}' is absolute: a scenario's library folders are relative to its file "
                                   "(give a machine's own folders with --libraries DIR)", p.string()));
            }
            const fs::path full = (folder / p).lexically_normal();
            if (!fs::is_directory(full)) d.fail(fmt::format("'{}' is not a folder ({})", p.string(), full.string()));
            if (const auto why = library_itself(full)) {
                d.fail(fmt::format("'{}' is a library itself ({}), not a folder of libraries: name the folder that "
                                   "holds it",
                                   p.string(), *why));
            }
            s.libraries.push_back(full);
        }
    }
    if (root["seed"]) s.seed = top.at(root["seed"], "seed").count();
    s.timeout = top.at(root["timeout"], "timeout").duration();
    if (s.timeout == 0) top.at(root["timeout"], "timeout").fail("must be longer than 0");
    if (root["pwm"]) {
        const Ctx c = top.at(root["pwm"], "pwm");
        const std::string v = c.str();
        if (v == "switched") s.pwm = plant::DriveMode::switched;
        else if (v == "averaged") s.pwm = plant::DriveMode::averaged;
        else c.fail(fmt::format("'{}' is not switched or averaged", v));
    }
    if (root["eeprom-timing"]) {
        const Ctx c = top.at(root["eeprom-timing"], "eeprom-timing");
        const std::string v = c.str();
        if (v == "datasheet") s.eeprom_timing = hil::EepromTimingMode::kDatasheet;
        else if (v == "instant") s.eeprom_timing = hil::EepromTimingMode::kInstant;
        else c.fail(fmt::format("'{}' is not datasheet or instant", v));
    }
    if (root["serial"]) {
        const Ctx c = top.at(root["serial"], "serial");
        c.keys({"baud", "port"});
        if (c.has("baud")) s.baud = static_cast<uint32_t>(c.child("baud").integer_in(300, 2000000));
        if (c.has("port")) {
            const Ctx p = c.child("port");
            const std::string name = p.str();
            const std::optional<int> usart = hil::parse_serial_port(board, name);
            if (!usart) {
                p.fail(fmt::format("'{}' is not a serial port of the {} ({}): {}", name, board.label, board.mcu->label,
                                   hil::serial_port_list(board)));
            }
            s.serial_usart = *usart;
            hil::check_host_serial_pins(s.board, board.mcu->usarts[static_cast<std::size_t>(*usart)]);
        }
    }
    if (root["eeprom"]) s.eeprom_preload = existing_file(top.at(root["eeprom"], "eeprom"));
    // Plant: embedded defaults, or a file, then overrides; the seed feeds the encoders.
    YAML::Node plant_yaml = YAML::Load(plant::emit_robot_params(plant::default_robot_params()));
    std::string plant_source = file.string() + " (plant)";
    if (root["plant"]) {
        const Ctx c = top.at(root["plant"], "plant");
        c.keys({"file", "overrides"});
        if (c.has("file")) {
            s.plant_file = existing_file(c.child("file"));
            plant::load_robot_params(*s.plant_file);  // its own messages name its file and line
            plant_yaml = YAML::LoadFile(s.plant_file->string());
        }
        if (c.has("overrides")) {
            const Ctx o = c.child("overrides");
            if (!o.node().IsMap()) o.fail("expected a mapping like {motor1: {resistance_ohm: 6.0}}");
            merge(plant_yaml, o.node());
        }
    }
    for (const char* enc : {"encoder1", "encoder2"}) {
        if (!plant_yaml[enc]) plant_yaml[enc] = YAML::Node(YAML::NodeType::Map);
        plant_yaml[enc]["seed"] = s.seed + (std::string(enc) == "encoder1" ? 0 : 1);
    }
    try {
        YAML::Emitter e;
        e << plant_yaml;
        s.plant = plant::parse_robot_params(e.c_str(), plant_source);
    } catch (const std::exception& e) {
        top.at(root["plant"] ? root["plant"] : root, "plant").fail(e.what());
    }
    // Steps.
    const Ctx steps = top.at(root["steps"], "steps");
    if (!root["steps"].IsSequence() || root["steps"].size() == 0) steps.fail("expected a non-empty list of steps");
    for (const auto& item : root["steps"]) {
        const Ctx sc = top.at(item, "steps[]");
        Step st;
        st.line = item.Mark().line + 1;
        // A step that takes no value may be written bare: `- reset`, `- expect-no-torn-reads`.
        if (item.IsScalar() && (item.Scalar() == "reset" || item.Scalar() == "expect-no-torn-reads")) {
            st.kind = item.Scalar();
            st.text = item.Scalar();
            st.action = parse_step(st.kind, top.at(YAML::Node(YAML::NodeType::Null), st.kind));
            s.steps.push_back(std::move(st));
            continue;
        }
        if (!item.IsMap() || item.size() != 1) {
            sc.fail("each step is a mapping with one key, e.g. - delay: 500ms (or a bare - reset / - expect-no-torn-reads)");
        }
        const std::string kind = item.begin()->first.Scalar();
        st.kind = kind;
        st.text = step_text(item);
        st.action = parse_step(kind, top.at(item.begin()->second, kind));
        s.steps.push_back(std::move(st));
    }
    return s;
}

Scenario load_scenario(const fs::path& file, const LoadOptions& options) {
    std::ifstream in(file, std::ios::binary);
    if (!in) throw ScenarioError(fmt::format("{}: cannot read the scenario file", file.string()));
    std::ostringstream text;
    text << in.rdbuf();
    return parse_scenario(text.str(), file, options);
}

}  // namespace ddmr::tools::scenario
