// The plant signals a scenario reads by name (wait-until, expect): truth.csv's
// columns and the wheel aliases (scenario.hpp).
#include "scenario/scenario.hpp"

#include <fmt/format.h>

#include <array>
#include <stdexcept>

#include "hil/plant_coupler.hpp"

namespace ddmr::tools::scenario {

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

const std::vector<std::string>& world_signal_names() {
    static const std::vector<std::string> names{"line_offset_m", "wall_distance_m", "contact", "contacts"};
    return names;
}

bool is_plant_signal(std::string_view name) { return find_signal(name) != nullptr; }

double plant_signal(const hil::TruthSample& t, std::string_view name) {
    const SignalDef* d = find_signal(name);
    if (d == nullptr) throw std::invalid_argument(fmt::format("'{}' is not a plant signal", name));
    return d->get(t);
}

}  // namespace ddmr::tools::scenario
