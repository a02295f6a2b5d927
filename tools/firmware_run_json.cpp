#include "firmware_run_json.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <optional>

#include "hil/cycle_time.hpp"

namespace ddmr::tools {
namespace {

using hil::Cycles;
using nlohmann::json;

json number_or_null(const std::optional<double>& v) {
    if (!v || !std::isfinite(*v)) return nullptr;
    return *v;
}

json stats_json(const hil::CycleDistribution& s, uint32_t clock_hz) {
    const double us = 1e6 / static_cast<double>(clock_hz);
    return json{{"count", s.count},
                {"min_cycles", s.min}, {"mean_cycles", s.mean}, {"p99_cycles", s.p99}, {"max_cycles", s.max},
                {"min_us", static_cast<double>(s.min) * us}, {"mean_us", s.mean * us},
                {"p99_us", static_cast<double>(s.p99) * us}, {"max_us", static_cast<double>(s.max) * us},
                {"histogram", {{"start_cycles", s.bin_start}, {"bin_width_cycles", s.bin_width}, {"counts", s.bins}}}};
}

}  // namespace

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

json contacts_json(const plant::Robot& robot) {
    json events = json::array();
    for (const plant::ContactEvent& e : robot.contacts()) {
        events.push_back({{"t_s", e.t_s}, {"x_m", e.x_m}, {"y_m", e.y_m}, {"speed_m_s", e.speed_m_s}, {"wall", e.wall}});
    }
    return json{{"count", robot.contact_count()}, {"in_contact_at_end", robot.in_contact()}, {"events", events}};
}

json pose_json(const plant::Pose& p) {
    return json{{"x_m", p.x_m}, {"y_m", p.y_m}, {"theta_rad", p.theta_rad}};
}

json encoder_json(const hil::BoardWiring& board, const std::array<hil::EncoderChannelStats, 2>& stats) {
    json encoder = json::object();
    for (unsigned ch = 0; ch < 2; ++ch) {
        const auto& s = stats[ch];
        const hil::EncoderWiring& w = board.wheel[ch].encoder;
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
    return encoder;
}

}  // namespace ddmr::tools
