#include "calibrate/log_objective.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <future>
#include <stdexcept>
#include <thread>

#include "calibrate/log_residual.hpp"
#include "hil/eeprom_log.hpp"

namespace ddmr::calibrate {
namespace {

namespace hs = ddmr::hostsim;

std::size_t range_end(const LogRun& run) { return run.end == 0 ? run.log.samples.size() : run.end; }

/// Metres of wheel travel per encoder edge of motor `m`.
double metres_per_edge(const plant::RobotParams& p, std::size_t m) {
    const plant::HallEncoderParams& e = p.encoder[m];
    const double edges_per_wheel_rev = e.edges_per_wheel_rev > 0.0
                                           ? e.edges_per_wheel_rev
                                           : static_cast<double>(e.edges_per_motor_rev) * p.motor[m].gear_ratio;
    const double radius = m == 0 ? p.kinematics.wheel_radius_right_m : p.kinematics.wheel_radius_left_m;
    return 2.0 * M_PI * radius / edges_per_wheel_rev;
}

/// A loss this large stands for a run that did not get there (the plant
/// stopped, or fewer samples were logged than the log has).
constexpr double kMissingSampleDistance_m = 10.0;

/// The simulation of `run` on `params` with the encoders at `phase`.
hs::SimResult simulate_at_phase(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config,
                                double phase) {
    hs::SimConfig c = config.base;
    c.model = hs::Model::ideal;  // every firmware switch but eeprom_bytes: the unquantised pose is logged
    c.fidelity = hs::Fidelity::all();
    c.fidelity.set(hs::FidelitySwitch::eeprom_bytes, false);
    // As long as the logged run: the sketch logs once every 10 iterations of
    // dt = 0.01 s (duration_s is on the controller's clock) and stops after
    // the last one, when it prints Count1 and Count2.
    c.duration_s = static_cast<double>(run.log.samples.size()) / 10.0;
    c.plant = params;
    c.plant.encoder[0].initial_phase = phase;
    c.plant.encoder[1].initial_phase = phase;
    return hs::simulate(c);
}

/// The simulations at every encoder phase, in the phases' order, on up to
/// config.threads threads (each simulation is independent: the order of the
/// results, and so every sum over them, does not depend on the threads).
std::vector<hs::SimResult> simulate_phases(const plant::RobotParams& params, const LogRun& run,
                                           const ObjectiveConfig& config) {
    const std::size_t n = config.encoder_phases.size();
    std::size_t threads = config.threads > 0 ? static_cast<std::size_t>(config.threads)
                                             : std::max(1U, std::thread::hardware_concurrency());
    threads = std::min(threads, n);
    std::vector<hs::SimResult> results(n);
    // Phase i on worker i % threads.
    const auto work = [&](std::size_t w) {
        for (std::size_t i = w; i < n; i += threads) results[i] = simulate_at_phase(params, run, config, config.encoder_phases[i]);
    };
    std::vector<std::future<void>> workers;
    for (std::size_t w = 1; w < threads; ++w) workers.push_back(std::async(std::launch::async, work, w));
    work(0);
    for (auto& f : workers) f.get();
    return results;
}

bool totals_count(const LogRun& run, const ObjectiveConfig& config) {
    return range_end(run) == run.log.samples.size() && config.count_weight > 0.0;
}

}  // namespace

void validate(const LogRun& run, const ObjectiveConfig& config) {
    const std::size_t end = range_end(run);
    if (end > run.log.samples.size() || run.first >= end) {
        throw std::invalid_argument(fmt::format("{}: samples [{}, {}) of {}: an empty or out-of-range part of the log",
                                                run.log.source, run.first, end, run.log.samples.size()));
    }
    if (config.encoder_phases.empty()) throw std::invalid_argument("no encoder phase to average over");
    for (const double ph : config.encoder_phases) {
        if (!(ph >= 0.0 && ph < 1.0)) throw std::invalid_argument(fmt::format("encoder phase {} is not in [0, 1)", ph));
    }
    if (!(config.loss_scale_m > 0.0)) throw std::invalid_argument("the loss scale must be > 0 m");
    if (!(config.count_weight >= 0.0)) throw std::invalid_argument("the count weight must be >= 0");
    if (config.threads < 0) throw std::invalid_argument("the thread count must be >= 0");
}

std::vector<double> predicted_log(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config) {
    validate(run, config);
    const std::size_t end = range_end(run);
    const std::size_t counted = end - run.first;
    const bool totals = totals_count(run, config);
    std::vector<double> out(2 * counted + (totals ? 2 : 0), 0.0);
    const double phases = static_cast<double>(config.encoder_phases.size());
    for (const hs::SimResult& r : simulate_phases(params, run, config)) {
        for (std::size_t k = run.first; k < end; ++k) {
            const bool have = k < r.eeprom_log.size();
            out[2 * (k - run.first)] += (have ? r.eeprom_log[k].x_m : kMissingSampleDistance_m) / phases;
            out[2 * (k - run.first) + 1] += (have ? r.eeprom_log[k].y_m : kMissingSampleDistance_m) / phases;
        }
        if (totals) {
            out[2 * counted] += static_cast<double>(r.samples.back().edges1) * metres_per_edge(config.base.plant, 0) / phases;
            out[2 * counted + 1] += static_cast<double>(r.samples.back().edges2) * metres_per_edge(config.base.plant, 1) / phases;
        }
    }
    return out;
}

std::vector<double> centre_residuals(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config) {
    std::vector<double> r = predicted_log(params, run, config);
    const std::size_t end = range_end(run);
    for (std::size_t k = run.first; k < end; ++k) {
        double& x = r[2 * (k - run.first)];
        double& y = r[2 * (k - run.first) + 1];
        x = cell_centre_residual_m(x, run.log.samples[k].x_byte);
        y = cell_centre_residual_m(y, run.log.samples[k].y_byte);
    }
    if (totals_count(run, config)) {
        const std::size_t counted = end - run.first;
        r[2 * counted] -= static_cast<double>(run.log.count1) * metres_per_edge(config.base.plant, 0);
        r[2 * counted + 1] -= static_cast<double>(run.log.count2) * metres_per_edge(config.base.plant, 1);
    }
    return r;
}

std::vector<std::pair<double, double>> logged_positions(const RobotLog& log) {
    std::vector<std::pair<double, double>> out;
    int x = 0;
    int y = 0;
    for (std::size_t k = 0; k < log.samples.size(); ++k) {
        const LoggedSample& s = log.samples[k];
        // Sample 0 signed (the robot starts at the origin), then the nearest value.
        x = k == 0 ? static_cast<int8_t>(s.x_byte) : hil::unwrap_counts(s.x_byte, x);
        y = k == 0 ? static_cast<int8_t>(s.y_byte) : hil::unwrap_counts(s.y_byte, y);
        out.emplace_back(x / kLogCountsPerMetre, y / kLogCountsPerMetre);
    }
    return out;
}

Evaluation evaluate(const plant::RobotParams& params, const LogRun& run, const ObjectiveConfig& config) {
    validate(run, config);
    const std::size_t end = range_end(run);
    const std::size_t counted = end - run.first;
    const auto logged = logged_positions(run.log);
    const double end_norm = std::hypot(logged[end - 1].first, logged[end - 1].second);

    Evaluation ev;
    const double phases = static_cast<double>(config.encoder_phases.size());
    for (const hs::SimResult& r : simulate_phases(params, run, config)) {
        if (r.status != plant::StepStatus::ok) ev.plant_failed = true;

        double loss = 0.0;
        double sum_sq = 0.0;
        double max_d = 0.0;
        double last_d = 0.0;
        for (std::size_t k = run.first; k < end; ++k) {
            double dx = kMissingSampleDistance_m;
            double dy = kMissingSampleDistance_m;
            if (k < r.eeprom_log.size()) {
                dx = cell_residual_m(r.eeprom_log[k].x_m, run.log.samples[k].x_byte);
                dy = cell_residual_m(r.eeprom_log[k].y_m, run.log.samples[k].y_byte);
            }
            loss += soft_l1(dx, config.loss_scale_m) + soft_l1(dy, config.loss_scale_m);
            const double d = std::hypot(dx, dy);
            sum_sq += d * d;
            max_d = std::max(max_d, d);
            last_d = d;
        }
        double terms = 2.0 * static_cast<double>(counted);
        const hs::SimSample& last = r.samples.back();
        if (totals_count(run, config)) {
            const double e1 = (static_cast<double>(last.edges1) - static_cast<double>(run.log.count1)) * metres_per_edge(config.base.plant, 0);
            const double e2 = (static_cast<double>(last.edges2) - static_cast<double>(run.log.count2)) * metres_per_edge(config.base.plant, 1);
            loss += config.count_weight * (soft_l1(e1, config.loss_scale_m) + soft_l1(e2, config.loss_scale_m));
            terms += 2.0 * config.count_weight;
        }
        ev.loss += loss / terms / phases;
        ev.metrics.rms_m += std::sqrt(sum_sq / static_cast<double>(counted)) / phases;
        ev.metrics.max_m += max_d / phases;
        ev.metrics.endpoint_m += last_d / phases;
        ev.metrics.count1 += static_cast<double>(last.edges1) / phases;
        ev.metrics.count2 += static_cast<double>(last.edges2) / phases;
    }
    ev.metrics.samples = counted;
    ev.metrics.endpoint_pct = end_norm > 0.0 ? 100.0 * ev.metrics.endpoint_m / end_norm : 0.0;
    return ev;
}

}  // namespace ddmr::calibrate
