#pragma once
// Reading a scenario file's YAML (scenario_yaml.cpp and the step parsers,
// step_parsers.hpp): a node with its key and line for messages ("FILE:LINE:
// key 'K': what is wrong", ScenarioError), and the readers of the values a
// scenario's keys take (paths, pins, operators, wheels, plant signals).

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>

#include <fmt/format.h>

#include "hil/board.hpp"
#include "scenario/scenario.hpp"
#include "scenario/scenario_yaml.hpp"

namespace ddmr::tools::scenario::yaml {
namespace fs = std::filesystem;

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
fs::path inside_folder(const Ctx& c);
/// inside_folder(), and an existing file.
fs::path existing_file(const Ctx& c);
/// A digital pin of the scenario's board: its number, or its silkscreen name
/// as a board file takes it ("D22", "A8").
int board_pin(const Ctx& c);
/// A timer-output pin that drives a motor driver input of the wiring.
int pwm_pin(const Ctx& c);
CompareOp compare_op(const Ctx& c);
/// Refuses a pattern std::regex (ECMAScript) cannot compile.
void check_regex(const Ctx& c, const std::string& pattern);
/// A wheel: 1 or `right` (motor 1), 2 or `left` (motor 2).
int wheel_number(const Ctx& c);
/// `[A, B]` with A <= B (refused otherwise), as expect's between and
/// expect-stats' mean take it.
Range min_max_pair(const Ctx& c);
/// The name of a plant signal (plant_signal_names()).
std::string plant_signal_name(const Ctx& c);
/// The step's optional `for:` duration.
std::optional<Cycles> optional_for(const Ctx& c);

}  // namespace ddmr::tools::scenario::yaml
