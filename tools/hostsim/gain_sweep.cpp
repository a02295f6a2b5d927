#include "tools/hostsim/gain_sweep.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace ddmr::hostsim {

namespace {

/// A2 group 1: v_g = 0.5 m/s (the line's speed), w_g = 0, every gain zero.
Gains line_gains() {
    Gains g;
    g.kx = 0.0;
    g.ky = 0.0;
    g.kw = 0.0;
    g.vref_m_s = 0.5;
    g.wref_rad_s = 0.0;
    return g;
}

/// A2 groups 2, 3 and fig. 5-7: "vg=0.3m/s, wg=0.3rad/s", every gain zero.
Gains circle_gains() {
    Gains g = line_gains();
    g.vref_m_s = 0.3;
    g.wref_rad_s = 0.3;
    return g;
}

Gains with(Gains g, double kx, double ky, double kw) {
    g.kx = kx;
    g.ky = ky;
    g.kw = kw;
    return g;
}

/// A2: "a 1 meter radius circle", "1-meter circle, 20 seconds".
CaseSpec one_metre_circle() {
    CaseSpec c = circle_case(1.0, 20.0);
    c.name = "circle-1m-20s";
    return c;
}

CaseSpec named_circle(double radius_m, double period_s, const char* name) {
    CaseSpec c = circle_case(radius_m, period_s);
    c.name = name;
    return c;
}

std::vector<Study> make_studies() {
    const CaseSpec step_x = line_step_case(StepAxis::x);
    const CaseSpec step_y = line_step_case(StepAxis::y);
    const CaseSpec circle = one_metre_circle();
    // A2's pages show these values (0, 1, 5, 10; for K_w and the circle's
    // K_y 0, 3, 5, 10); "the influence of each variable is charted for a
    // gain of 0 through 10" (ch. 5).
    const std::vector<double> a2_kx{0.0, 1.0, 5.0, 10.0};
    const std::vector<double> a2_ky_line{0.0, 1.0, 5.0, 10.0};
    const std::vector<double> a2_three{0.0, 3.0, 5.0, 10.0};
    const std::vector<double> kx_half_to_two{0.5, 1.0, 1.5, 2.0};

    std::vector<Study> s;
    s.push_back({"fig5_2", "Figure 5-2", "K_x sensitivity to a 20 cm step in X; K_y = K_w = 0, v_g = 0.5 m/s, w_g = 0",
                 {step_x}, SweptGain::kx, a2_kx, line_gains(), false});
    s.push_back({"fig5_3", "Figure 5-3", "K_y sensitivity to a 20 cm step in Y; K_x = K_w = 0, v_g = 0.5 m/s, w_g = 0",
                 {step_y}, SweptGain::ky, a2_ky_line, line_gains(), false});
    s.push_back({"fig5_4", "Figure 5-4", "K_w sensitivity to a 20 cm step in Y; K_x = K_y = 0, v_g = 0.5 m/s, w_g = 0",
                 {step_y}, SweptGain::kw, a2_three, line_gains(), false});
    s.push_back({"a2_circle_kx", "Appendix A2",
                 "K_x sensitivity on the 1 m, 20 s circle; K_y = K_w = 0, v_g = 0.3 m/s, w_g = 0.3 rad/s",
                 {circle}, SweptGain::kx, a2_kx, circle_gains(), false});
    s.push_back({"a2_circle_ky", "Appendix A2",
                 "K_y sensitivity on the 1 m, 20 s circle; K_x = K_w = 0, v_g = 0.3 m/s, w_g = 0.3 rad/s",
                 {circle}, SweptGain::ky, a2_three, circle_gains(), false});
    s.push_back({"a2_circle_kw", "Appendix A2",
                 "K_w sensitivity on the 1 m, 20 s circle; K_x = K_y = 0, v_g = 0.3 m/s, w_g = 0.3 rad/s",
                 {circle}, SweptGain::kw, a2_three, circle_gains(), false});
    s.push_back({"fig5_5", "Figure 5-5", "Impact of K_y = 5 as K_x varies; K_w = 0, 1 m, 20 s circle",
                 {circle}, SweptGain::kx, kx_half_to_two, with(circle_gains(), 0.0, 5.0, 0.0), false});
    s.push_back({"fig5_6", "Figure 5-6", "Impact of K_w = 5 as K_x varies; K_y = 0, 1 m, 20 s circle",
                 {circle}, SweptGain::kx, kx_half_to_two, with(circle_gains(), 0.0, 0.0, 5.0), false});
    // The thesis names no values for fig. 5-7; A2's K_w values plus the
    // K_w = 8 it settles on ("slightly underdamped").
    s.push_back({"fig5_7", "Figure 5-7", "K_w sensitivity with K_x = 1, K_y = 6; 1 m, 20 s circle",
                 {circle}, SweptGain::kw, {0.0, 3.0, 5.0, 8.0, 10.0}, with(circle_gains(), 1.0, 6.0, 0.0), false});
    const Gains aggressive = with(Gains{}, 2.0, 12.0, 18.0);
    s.push_back({"fig5_8", "Figure 5-8",
                 "Robustness of aggressive settings K_x = 2, K_y = 12, K_w = 18 on 0.4 m / 8 s and 0.6 m / 12 s "
                 "circles; v_g, w_g = the goal's velocity",
                 {named_circle(0.4, 8.0, "circle-0.4m-8s"), named_circle(0.6, 12.0, "circle-0.6m-12s")},
                 SweptGain::none, {}, aggressive, /*goal_feedforward=*/true});
    return s;
}

/// "unknown study 'x' (known: fig5_2, ..., all)"
std::string unknown_study_message(const std::string& id, const std::vector<Study>& all) {
    std::string known;
    for (const Study& s : all) known += (known.empty() ? "" : ", ") + s.id;
    return "unknown study '" + id + "' (known: " + known + ", all)";
}

}  // namespace

const char* to_string(SweptGain g) {
    switch (g) {
        case SweptGain::kx: return "kx";
        case SweptGain::ky: return "ky";
        case SweptGain::kw: return "kw";
        case SweptGain::none: return "none";
    }
    return "?";
}

const std::vector<Study>& thesis_studies() {
    static const std::vector<Study> studies = make_studies();
    return studies;
}

std::vector<Study> select_studies(const std::string& ids) {
    const std::vector<Study>& all = thesis_studies();
    if (ids.empty() || ids == "all") return all;
    std::vector<Study> chosen;
    std::size_t begin = 0;
    while (begin <= ids.size()) {
        const std::size_t comma = std::min(ids.find(',', begin), ids.size());
        const std::string id = ids.substr(begin, comma - begin);
        begin = comma + 1;
        const auto it = std::find_if(all.begin(), all.end(), [&](const Study& s) { return s.id == id; });
        if (it == all.end()) throw std::invalid_argument(unknown_study_message(id, all));
        const bool seen =
            std::any_of(chosen.begin(), chosen.end(), [&](const Study& s) { return s.id == id; });
        if (!seen) chosen.push_back(*it);
    }
    return chosen;
}

std::vector<StudyRun> study_runs(const Study& s) {
    std::vector<StudyRun> runs;
    for (const CaseSpec& c : s.trajectories) {
        Gains g = s.fixed;
        if (s.goal_feedforward) {
            const GoalVelocity v = goal_velocity(c);
            g.vref_m_s = v.v_m_s;
            g.wref_rad_s = v.omega_rad_s;
        }
        if (s.varied == SweptGain::none) {
            runs.push_back({c, 0.0, g});
            continue;
        }
        for (double value : s.values) {
            StudyRun r{c, value, g};
            if (s.varied == SweptGain::kx) r.gains.kx = value;
            if (s.varied == SweptGain::ky) r.gains.ky = value;
            if (s.varied == SweptGain::kw) r.gains.kw = value;
            runs.push_back(r);
        }
    }
    return runs;
}

SimConfig run_config(const SimConfig& base, const StudyRun& run) {
    SimConfig c = base;
    c.case_spec = run.case_spec;
    c.gains = run.gains;
    c.duration_s = run.case_spec.duration_s;
    c.sample_period_s = kSweepSamplePeriod_s;
    return c;
}

std::vector<SimResult> simulate_parallel(const std::vector<SimConfig>& configs, unsigned workers,
                                         const std::function<void(std::size_t)>& on_done) {
    for (std::size_t i = 0; i < configs.size(); ++i) {
        try {
            validate(configs[i]);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument("run " + std::to_string(i) + ": " + e.what());
        }
    }
    std::vector<SimResult> results(configs.size());
    if (configs.empty()) return results;
    if (workers == 0) workers = std::max(1u, std::thread::hardware_concurrency());
    workers = static_cast<unsigned>(std::min<std::size_t>(workers, configs.size()));

    // Each worker takes the next index; results and errors go to that index.
    std::atomic<std::size_t> next{0};
    std::vector<std::exception_ptr> errors(configs.size());
    std::mutex done_mutex;
    auto work = [&] {
        for (std::size_t i = next.fetch_add(1); i < configs.size(); i = next.fetch_add(1)) {
            try {
                results[i] = simulate(configs[i]);
            } catch (...) {
                errors[i] = std::current_exception();  // e.g. bad_alloc; simulate never throws once running
            }
            if (on_done) {
                const std::lock_guard<std::mutex> lock(done_mutex);
                on_done(i);
            }
        }
    };
    std::vector<std::thread> pool;
    pool.reserve(workers);
    for (unsigned w = 0; w < workers; ++w) pool.emplace_back(work);
    for (std::thread& t : pool) t.join();
    for (const std::exception_ptr& e : errors) {
        if (e) std::rethrow_exception(e);
    }
    return results;
}

TrackingMetrics tracking_metrics(const SimResult& r, const CaseSpec& c, double band_m) {
    if (r.samples.empty()) throw std::invalid_argument("tracking_metrics: the run has no samples");
    const double start_s = c.kind == CaseKind::line_step ? c.step_time_s : 0.0;
    TrackingMetrics m;
    double sum_sq = 0.0;
    // The first sample at or after start_s from which the error stays in band.
    bool inside = false;
    double inside_since_s = 0.0;
    for (const SimSample& s : r.samples) {
        const double e = std::hypot(s.goal_x_m - s.x_m, s.goal_y_m - s.y_m);
        sum_sq += e * e;
        m.max_error_m = std::max(m.max_error_m, e);
        m.final_error_m = e;
        if (s.t_s < start_s) continue;
        if (e > band_m) {
            inside = false;
        } else if (!inside) {
            inside = true;
            inside_since_s = s.t_s;
        }
    }
    m.rms_error_m = std::sqrt(sum_sq / static_cast<double>(r.samples.size()));
    if (inside) m.settling_time_s = inside_since_s - start_s;
    return m;
}

std::string sweep_plot_script() { return DDMR_PLOT_SWEEP_SCRIPT; }

}  // namespace ddmr::hostsim
