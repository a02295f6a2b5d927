#include "calibrate/calibration.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string_view>

#include "calibrate/least_squares.hpp"
#include "plant/param_access.hpp"

namespace ddmr::calibrate {
namespace {

constexpr std::string_view kBackEmf = ".back_emf_V_s_per_rad";
constexpr std::string_view kTorque = ".torque_N_m_per_A";

/// A plant with `values` set at `keys`. A motor's torque constant follows
/// its back-EMF constant (the same ratio to the start) unless it is fitted
/// itself: in SI units they are one constant of the motor.
plant::RobotParams with_values(const plant::RobotParams& base, const std::vector<std::string>& keys,
                               const std::vector<double>& values) {
    plant::RobotParams p = base;
    for (std::size_t i = 0; i < keys.size(); ++i) {
        double* v = plant::find_param(p, keys[i])->value;
        for (const std::string& follower : param_keys_tied_to(keys[i])) {
            if (std::find(keys.begin(), keys.end(), follower) == keys.end()) *plant::find_param(p, follower)->value *= values[i] / *v;
        }
        *v = values[i];
    }
    return p;
}

/// The predicted logs of every run, one after the other.
std::vector<double> predict_all(const plant::RobotParams& p, const std::vector<LogRun>& runs, const ObjectiveConfig& objective) {
    std::vector<double> out;
    for (const LogRun& run : runs) {
        const std::vector<double> y = predicted_log(p, run, objective);
        out.insert(out.end(), y.begin(), y.end());
    }
    return out;
}

void say(const CalibrationSetup& setup, const std::string& line) {
    if (setup.stage) setup.stage(line);
}

}  // namespace

std::vector<std::string> param_keys_tied_to(const std::string& key) {
    if (key.size() > kBackEmf.size() && key.compare(key.size() - kBackEmf.size(), kBackEmf.size(), kBackEmf) == 0) {
        return {key.substr(0, key.size() - kBackEmf.size()) + std::string(kTorque)};
    }
    return {};
}

std::string tied_to(const std::string& key, const std::vector<std::string>& fitted) {
    if (std::find(fitted.begin(), fitted.end(), key) != fitted.end()) return {};
    for (const std::string& f : fitted) {
        for (const std::string& follower : param_keys_tied_to(f)) {
            if (follower == key) return f;
        }
    }
    return {};
}

const std::vector<std::string>& default_candidate_keys() {
    static const std::vector<std::string> keys = {
        "motor1.resistance_ohm",       "motor2.resistance_ohm",       "motor1.back_emf_V_s_per_rad",
        "motor2.back_emf_V_s_per_rad", "motor1.coulomb_friction_N_m", "motor2.coulomb_friction_N_m",
        "driver.drop_V",
    };
    return keys;
}

void make_runs(const CalibrationSetup& setup, std::vector<LogRun>& train, std::vector<LogRun>& holdout) {
    train.clear();
    holdout.clear();
    if (setup.logs.empty()) throw std::invalid_argument("no log to fit");
    if (setup.split && !(*setup.split > 0.0 && *setup.split < 1.0)) {
        throw std::invalid_argument(fmt::format("--split {}: not in (0, 1)", *setup.split));
    }
    for (const RobotLog& log : setup.logs) {
        const std::size_t n = log.samples.size();
        if (!setup.split) {
            train.push_back({log, 0, 0});
            continue;
        }
        const auto cut = static_cast<std::size_t>(std::floor(*setup.split * static_cast<double>(n)));
        if (cut == 0 || cut >= n) {
            throw std::invalid_argument(fmt::format("{}: --split {} of its {} samples leaves nothing to {}", log.source,
                                                    *setup.split, n, cut == 0 ? "fit" : "judge"));
        }
        train.push_back({log, 0, cut});
        holdout.push_back({log, cut, 0});
    }
    for (const RobotLog& log : setup.holdout_logs) holdout.push_back({log, 0, 0});
    for (const LogRun& r : train) validate(r, setup.objective);
    for (const LogRun& r : holdout) validate(r, setup.objective);
}

SetScore score(const plant::RobotParams& params, const std::vector<LogRun>& runs, const ObjectiveConfig& objective) {
    SetScore s;
    double sum_sq = 0.0;
    for (const LogRun& run : runs) {
        const Evaluation ev = evaluate(params, run, objective);
        SetScore::PerLog l;
        l.source = run.log.source;
        l.metrics = ev.metrics;
        l.totals = run.end == 0 || run.end == run.log.samples.size();
        l.logged_count1 = run.log.count1;
        l.logged_count2 = run.log.count2;
        s.logs.push_back(l);
        sum_sq += ev.metrics.rms_m * ev.metrics.rms_m * static_cast<double>(ev.metrics.samples);
        s.samples += ev.metrics.samples;
        s.max_m = std::max(s.max_m, ev.metrics.max_m);
        s.endpoint_m += ev.metrics.endpoint_m / static_cast<double>(runs.size());
        s.endpoint_pct += ev.metrics.endpoint_pct / static_cast<double>(runs.size());
    }
    if (s.samples > 0) s.rms_m = std::sqrt(sum_sq / static_cast<double>(s.samples));
    return s;
}

/// The parameters a fit may search: --fit's keys (each checked), else the
/// default candidates that are positive in the starting plant (the others in
/// out.not_fitted), with their starting values.
struct Candidates {
    std::vector<std::string> keys;
    std::vector<double> start_values;
};

Candidates candidates_of(const CalibrationSetup& setup, CalibrationResult& out) {
    const bool chosen_by_data = setup.keys.empty();
    Candidates c;
    std::vector<double>& start_values = c.start_values;
    std::vector<std::string>& candidate_list = c.keys;
    const std::vector<std::string>& candidates = chosen_by_data ? default_candidate_keys() : setup.keys;
    plant::RobotParams scratch = setup.start;
    for (const std::string& key : candidates) {
        // A default candidate at 0 in the starting plant (no friction, an
        // ideal driver) is left out, not an error: there is nothing to scale.
        if (chosen_by_data) {
            const auto ref = plant::find_param(scratch, key);
            if (!(*ref->value > 0.0)) {
                out.not_fitted.emplace_back(key, fmt::format("it is {} in the starting plant: a fit searches around a "
                                                             "positive start (set one with --plant, or --fit it)",
                                                             *ref->value));
                continue;
            }
        }
        if (std::count(candidates.begin(), candidates.end(), key) > 1) {
            throw std::invalid_argument(fmt::format("--fit {}: given twice", key));
        }
        const auto ref = plant::find_param(scratch, key);
        if (!ref) {
            throw std::invalid_argument(fmt::format("--fit {}: not a real-valued plant parameter (the keys are those "
                                                    "of a plant file: docs/plant.md)",
                                                    key));
        }
        if (!(*ref->value > 0.0)) {
            throw std::invalid_argument(fmt::format("--fit {}: it is {} in the starting plant; a fit searches around a "
                                                    "positive start (set one with --plant)",
                                                    key, *ref->value));
        }
        start_values.push_back(*ref->value);
        candidate_list.push_back(key);
    }
    return c;
}

/// The keys to fit: those the start's sensitivities `s0` pin down (chosen by
/// the data; the others in out.not_fitted), or --fit's, each of which must be.
std::vector<std::string> chosen_keys(const CalibrationSetup& setup, const Eigen::MatrixXd& s0, const Candidates& c,
                                     CalibrationResult& out) {
    const bool chosen_by_data = setup.keys.empty();
    const std::vector<std::string>& candidate_list = c.keys;
    const std::vector<double>& start_values = c.start_values;
    std::vector<std::string> keys;
    if (chosen_by_data) {
        const Selection sel = select_identifiable(s0, candidate_list, start_values, setup.max_half_width, log_noise_m(),
                                                  setup.model_tolerance_m);
        for (const std::size_t j : sel.chosen) keys.push_back(candidate_list[j]);
        for (const auto& l : sel.left_out) out.not_fitted.emplace_back(candidate_list[l.index], l.reason);
        if (keys.empty()) throw std::runtime_error("the logs pin down none of the plant's parameters");
    } else {
        const Identifiability a = analyse_sensitivities(s0, candidate_list, start_values, log_noise_m(), setup.model_tolerance_m);
        for (const ParamIdentifiability& p : a.params) {
            if (p.identifiable) continue;
            const bool phase = p.key.size() > 14 && p.key.compare(p.key.size() - 14, 14, ".initial_phase") == 0;
            throw UnidentifiableParameter(fmt::format("--fit {}: {}", p.key,
                                                      phase ? "the fit averages over the encoder phases (--phases) "
                                                              "instead of fitting them"
                                                            : p.reason));
        }
        keys = candidate_list;
    }
    return keys;
}

/// Each key's search interval: its start divided and multiplied by the range
/// factor, within the parameter's own range (also out.params' start and bounds).
std::vector<FitParam> search_box(const CalibrationSetup& setup, const std::vector<std::string>& keys,
                                 CalibrationResult& out) {
    plant::RobotParams scratch = setup.start;
    std::vector<FitParam> box;
    for (const std::string& key : keys) {
        const auto ref = plant::find_param(scratch, key);
        const double v = *ref->value;
        FittedParam fp;
        fp.key = key;
        fp.unit = ref->unit;
        fp.start = v;
        fp.lo = std::max(v / setup.range_factor, ref->range.lo);
        fp.hi = std::min(v * setup.range_factor, ref->range.hi);
        out.params.push_back(fp);
        box.push_back({key, v, fp.lo, fp.hi});
    }
    return box;
}

/// The warnings of a fit: the logs' own, a spent least-squares budget, a
/// residual above the quantisation, a value at its search bound.
void add_fit_warnings(const CalibrationSetup& setup, const std::vector<std::string>& keys,
                      const std::vector<FitParam>& box, CalibrationResult& out) {
    // The logs' own warnings (a dump without its unwritten last line) first.
    for (const std::vector<RobotLog>* logs : {&setup.logs, &setup.holdout_logs}) {
        for (const RobotLog& l : *logs) out.warnings.insert(out.warnings.end(), l.warnings.begin(), l.warnings.end());
    }
    if (out.least_squares.stop == "the evaluation budget is spent") {
        out.warnings.push_back(fmt::format("the least-squares stage spent its budget ({} evaluations) before it "
                                           "converged: give a larger --lm-evals",
                                           out.least_squares.evaluations));
    }
    if (out.residual_rms_m > 2.0 * log_noise_m()) {
        out.warnings.push_back(fmt::format("the fitted plant stays {:.1f} mm RMS from the log's cells' centres (the "
                                           "quantisation alone gives {:.1f} mm): the model or the start is off, and "
                                           "the intervals are widened by it",
                                           out.residual_rms_m * 1e3, log_noise_m() * 1e3));
    }
    for (std::size_t i = 0; i < keys.size(); ++i) {
        const FitParam& b = box[i];
        const double v = out.fit.values[i];
        if (v <= b.lo * (1.0 + 1e-6) || v >= b.hi * (1.0 - 1e-6)) {
            out.warnings.push_back(fmt::format("{} = {:.6g} is at its search bound [{:.6g}, {:.6g}]", keys[i], v, b.lo, b.hi));
        }
    }
}

CalibrationResult calibrate(const CalibrationSetup& setup) {
    if (!(setup.range_factor > 1.0)) throw std::invalid_argument("the search range factor must be > 1");
    CalibrationResult out;
    make_runs(setup, out.train, out.holdout);

    const Candidates c = candidates_of(setup, out);
    const std::vector<std::string>& candidate_list = c.keys;
    const std::vector<double>& start_values = c.start_values;

    // What the fitted logs show of each candidate, at the start.
    if (candidate_list.empty()) throw std::runtime_error("no candidate parameter is positive in the starting plant");
    say(setup, fmt::format("sensitivities of {} parameter(s) at the start ({} simulations)", candidate_list.size(),
                           2 * candidate_list.size() * out.train.size() * setup.objective.encoder_phases.size()));
    const auto predict = [&](const std::vector<std::string>& keys) {
        return [&setup, &out, keys](const std::vector<double>& v) {
            return predict_all(with_values(setup.start, keys, v), out.train, setup.objective);
        };
    };
    // The same step as the least squares' Jacobian: small steps see the encoders' jumps.
    const double step = setup.least_squares.relative_step;
    const Eigen::MatrixXd s0 = sensitivity_matrix(predict(candidate_list), start_values, step);
    const std::vector<std::string> keys = chosen_keys(setup, s0, c, out);

    std::vector<FitParam> box = search_box(setup, keys, out);
    say(setup, fmt::format("fitting {} on {} log part(s)", fmt::join(keys, ", "), out.train.size()));
    const auto loss = [&](const std::vector<double>& v) {
        const plant::RobotParams p = with_values(setup.start, keys, v);
        double sum = 0.0;
        for (const LogRun& run : out.train) sum += evaluate(p, run, setup.objective).loss;
        return sum / static_cast<double>(out.train.size());
    };
    // Least squares on the cells' centres (fast, smooth), then the robust
    // loss from there (derivative-free: it is flat inside the cells).
    const auto residuals = [&](const std::vector<double>& v) {
        const plant::RobotParams p = with_values(setup.start, keys, v);
        std::vector<double> r;
        for (const LogRun& run : out.train) {
            const std::vector<double> x = centre_residuals(p, run, setup.objective);
            r.insert(r.end(), x.begin(), x.end());
        }
        return r;
    };
    out.least_squares = fit_least_squares(box, residuals, setup.least_squares);
    say(setup, fmt::format("least squares: {} evaluations, {}; then the robust loss", out.least_squares.evaluations,
                           out.least_squares.stop));
    for (std::size_t i = 0; i < box.size(); ++i) box[i].start = out.least_squares.values[i];
    out.fit = fit(box, loss, setup.fit);
    out.fitted = with_values(setup.start, keys, out.fit.values);

    // The noise the intervals assume: the quantisation's, or the fit's own
    // residual when that is larger (a fit that does not reach the cells
    // cannot claim the cells' precision).
    double residual_ss = 0.0;
    const std::vector<double> final_residuals = residuals(out.fit.values);
    for (const double x : final_residuals) residual_ss += x * x;
    out.residual_rms_m = std::sqrt(residual_ss / static_cast<double>(final_residuals.size()));
    const double sigma = std::max(log_noise_m(), out.residual_rms_m);
    say(setup, "intervals at the fitted point");
    out.identifiability = analyse_identifiability(predict(keys), keys, out.fit.values, sigma, step, setup.model_tolerance_m);
    add_fit_warnings(setup, keys, box, out);
    for (std::size_t i = 0; i < keys.size(); ++i) {
        out.params[i].value = out.fit.values[i];
        out.params[i].at_fit = out.identifiability.params[i];
    }
    say(setup, "scoring before and after");
    out.before_train = score(setup.start, out.train, setup.objective);
    out.after_train = score(out.fitted, out.train, setup.objective);
    if (!out.holdout.empty()) {
        out.before_holdout = score(setup.start, out.holdout, setup.objective);
        out.after_holdout = score(out.fitted, out.holdout, setup.objective);
    }
    return out;
}

}  // namespace ddmr::calibrate
