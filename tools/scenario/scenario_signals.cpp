#include "scenario/scenario_signals.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hil/elf_image.hpp"
#include "hil/plant_coupler.hpp"
#include "scenario/scenario_yaml.hpp"
#include "scenario/step_failed.hpp"

namespace ddmr::tools::scenario {
namespace {

/// The signal a step names, or null.
const std::string* signal_of(const StepAction& a) {
    if (const auto* w = std::get_if<WaitUntil>(&a)) return &w->signal;
    if (const auto* e = std::get_if<ExpectSignal>(&a)) return &e->signal;
    if (const auto* m = std::get_if<Measure>(&a)) return &m->signal;
    if (const auto* x = std::get_if<ExpectStats>(&a)) return &x->signal;
    return nullptr;
}

std::string list(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out.empty() ? "none" : out;
}

}  // namespace

hil::RigConfig rig_config_of(const Scenario& s) {
    hil::RigConfig config;
    config.plant = s.plant;
    config.board = s.board;
    config.world = s.world;
    config.coupler.mode = s.pwm;
    config.eeprom_timing = s.eeprom_timing;
    config.host_usart = s.serial_usart;
    return config;
}

void check_signal_names(const Scenario& s) {
    const bool any = std::any_of(s.steps.begin(), s.steps.end(), [](const Step& step) {
        const std::string* name = signal_of(step.action);
        return name != nullptr && !is_plant_signal(*name);
    });
    if (!any) return;
    const hil::ElfImage elf = hil::ElfImage::read(s.firmware);
    hil::RobotRig rig(elf, rig_config_of(s));
    RigSignals(rig).check_steps(s);
}

RigSignals::RigSignals(hil::RobotRig& rig) : rig_(rig), extra_(rig.extra_truth_columns()) {}

bool RigSignals::has(const std::string& name) const {
    return is_plant_signal(name) || std::find(extra_.begin(), extra_.end(), name) != extra_.end();
}

void RigSignals::check_steps(const Scenario& s) const {
    for (const Step& step : s.steps) {
        const std::string* name = signal_of(step.action);
        if (name == nullptr || has(*name)) continue;
        throw ScenarioError(fmt::format("{}:{}: key '{}.signal': this robot has no signal '{}' (its world and parts "
                                        "give: {})",
                                        s.file.string(), step.line, step.kind, *name, list(extra_)));
    }
}

std::size_t RigSignals::extra_index(const std::string& name) const {
    const auto it = std::find(extra_.begin(), extra_.end(), name);
    if (it == extra_.end()) throw std::logic_error("RigSignals: '" + name + "' was not checked");
    return static_cast<std::size_t>(it - extra_.begin());
}

double RigSignals::now(const std::string& name) const {
    if (is_plant_signal(name)) return plant_signal(hil::truth_sample_of(rig_.robot(), rig_.core().cycle()), name);
    values_.clear();
    rig_.extra_truth_values(values_);
    return values_[extra_index(name)];
}

void RigSignals::measure(const std::string& name) { stats_[name] = Stats{}; }

void RigSignals::on_truth(const hil::TruthSample& sample) {
    if (stats_.empty()) return;
    values_.clear();
    rig_.extra_truth_values(values_);  // once for every measured signal of this sample
    for (auto& [name, st] : stats_) {
        const double v = is_plant_signal(name) ? plant_signal(sample, name) : values_[extra_index(name)];
        st.min = st.n == 0 ? v : std::min(st.min, v);
        st.max = st.n == 0 ? v : std::max(st.max, v);
        st.sum += v;
        st.sum_sq += v * v;
        ++st.n;
    }
}

std::string RigSignals::expect_stats(const ExpectStats& e) const {
    const auto it = stats_.find(e.signal);
    if (it == stats_.end()) {
        throw StepFailed{Verdict::kFail, fmt::format("{} is not measured: a measure step must come first", e.signal)};
    }
    const Stats& st = it->second;
    const double n = static_cast<double>(st.n);
    const double mean = st.n > 0 ? st.sum / n : 0.0;
    const double rms = st.n > 0 ? std::sqrt(st.sum_sq / n) : 0.0;
    const double abs_max = std::max(std::fabs(st.min), std::fabs(st.max));
    std::string seen = fmt::format("{} over {} samples: rms {:.6g}, mean {:.6g}, min {:.6g}, max {:.6g}",
                                         e.signal, st.n, rms, mean, st.min, st.max);
    const auto fail = [&](const std::string& what) { throw StepFailed{Verdict::kFail, what + "; " + seen}; };
    if (st.n < e.min_samples) fail(fmt::format("expected at least {} samples", e.min_samples));
    if (e.rms_max && rms > *e.rms_max) fail(fmt::format("expected rms <= {:.6g}", *e.rms_max));
    if (e.abs_max && abs_max > *e.abs_max) fail(fmt::format("expected |{}| <= {:.6g}", e.signal, *e.abs_max));
    if (e.range.set() && !(e.range.contains(st.min) && e.range.contains(st.max))) {
        fail(fmt::format("expected every sample in [{:.6g}, {:.6g}]", e.range.min.value_or(-INFINITY),
                         e.range.max.value_or(INFINITY)));
    }
    if (e.mean.set() && !e.mean.contains(mean)) {
        fail(fmt::format("expected the mean in [{:.6g}, {:.6g}]", e.mean.min.value_or(-INFINITY),
                         e.mean.max.value_or(INFINITY)));
    }
    return seen;
}

}  // namespace ddmr::tools::scenario
