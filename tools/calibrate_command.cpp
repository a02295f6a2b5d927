#include "calibrate_command.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "calibrate/calibration.hpp"
#include "calibrate_hil_check.hpp"
#include "common/atomic_file.hpp"
#include "common/svg_xy_plot.hpp"
#include "exit_codes.hpp"
#include "firmware_run.hpp"
#include "hil/elf_image.hpp"
#include "hil/mcu.hpp"
#include "plant/param_access.hpp"
#include "plant/params_yaml.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
namespace cal = ddmr::calibrate;

struct CalibrateCli {
    std::vector<std::string> logs;
    std::vector<std::string> holdout;
    std::optional<double> split;
    std::optional<int> case_number;
    std::vector<std::string> fit_keys;
    std::string plant;
    std::string out = "out/calibrate";
    int64_t seed = 1;
    int lm_evaluations = 250;
    int global_evaluations = 0;
    int local_evaluations = 60;
    int phases = 4;
    double period_ms = 10.44;
    bool no_hil = false;
    std::string firmware = DDMR_DEFAULT_FIRMWARE;
    bool quiet = false;
};

/// The case all logs come from: --case, else their banners (which must agree).
int case_of(const CalibrateCli& o, const std::vector<cal::RobotLog>& logs) {
    if (o.case_number && *o.case_number != 1 && *o.case_number != 2) {
        throw std::invalid_argument(fmt::format("--case {}: the sketch has cases 1 and 2 only", *o.case_number));
    }
    std::optional<int> banner;
    for (const cal::RobotLog& l : logs) {
        if (!l.case_number) continue;
        if (o.case_number && *l.case_number != *o.case_number) {
            throw std::invalid_argument(fmt::format("{}: its banner says case {}, --case says {}", l.source,
                                                    *l.case_number, *o.case_number));
        }
        if (banner && *banner != *l.case_number) {
            throw std::invalid_argument(fmt::format("{}: case {}, but another log is case {}: calibrate one case at a time",
                                                    l.source, *l.case_number, *banner));
        }
        banner = l.case_number;
    }
    const int c = o.case_number ? *o.case_number : banner.value_or(0);
    if (c == 0) throw std::invalid_argument("no log has a case banner (\"0.6m\"): give --case 1");
    if (!hostsim::firmware_case(c).logs_eeprom) {
        throw std::invalid_argument(fmt::format("--case {}: the sketch logs no EEPROM track in that case; only case 1 "
                                                "can be calibrated from",
                                                c));
    }
    return c;
}

/// `text` as one CSV field (RFC 4180: quoted when it holds a comma, a quote or a line break).
std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
    std::string q = "\"";
    for (const char c : text) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

/// A LOG as given: a dump, or an output folder of `run` or `scenario` (its uart.txt).
fs::path log_file(const std::string& given) {
    fs::path p(given);
    if (!fs::is_directory(p)) return p;
    if (!fs::is_regular_file(p / "uart.txt")) {
        throw std::invalid_argument(fmt::format("{}: a folder without uart.txt (give a serial dump, or the output "
                                                "folder of `ddmr-hil run` or of a scenario)",
                                                given));
    }
    return p / "uart.txt";
}

nlohmann::json metrics_json(const cal::SetScore& s) {
    nlohmann::json logs = nlohmann::json::array();
    double c1 = 0.0, c2 = 0.0;
    uint64_t l1 = 0, l2 = 0;
    bool totals = false;
    for (const auto& l : s.logs) {
        nlohmann::json j = {{"log", l.source},         {"rms_m", l.metrics.rms_m},
                            {"max_m", l.metrics.max_m}, {"endpoint_m", l.metrics.endpoint_m},
                            {"endpoint_pct", l.metrics.endpoint_pct}, {"samples", l.metrics.samples}};
        if (l.totals) {
            j["count1"] = l.metrics.count1;
            j["count2"] = l.metrics.count2;
            j["logged_count1"] = l.logged_count1;
            j["logged_count2"] = l.logged_count2;
            c1 += l.metrics.count1;
            c2 += l.metrics.count2;
            l1 += l.logged_count1;
            l2 += l.logged_count2;
            totals = true;
        }
        logs.push_back(j);
    }
    nlohmann::json j = {{"rms_m", s.rms_m},     {"max_m", s.max_m},     {"endpoint_m", s.endpoint_m},
                        {"endpoint_pct", s.endpoint_pct}, {"samples", s.samples}, {"logs", logs}};
    // The encoder totals summed over the logs whose end is judged here.
    if (totals) {
        j["count1"] = c1;
        j["count2"] = c2;
        j["logged_count1"] = l1;
        j["logged_count2"] = l2;
    } else {
        j["count1"] = nullptr;
        j["count2"] = nullptr;
    }
    return j;
}

/// emit_robot_params with a comment after each fitted value and a header.
std::string plant_yaml(const cal::CalibrationResult& r, const std::string& header) {
    std::vector<std::string> fitted_keys;
    for (const cal::FittedParam& p : r.params) fitted_keys.push_back(p.key);
    std::istringstream in(plant::emit_robot_params(r.fitted));
    std::string out = header;
    std::string section;
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line[0] != ' ') section = line.substr(0, line.find(':'));
        const auto colon = line.find(':');
        if (!line.empty() && line[0] == ' ' && colon != std::string::npos) {
            const std::size_t first = line.find_first_not_of(' ');
            const std::string key = section + "." + line.substr(first, colon - first);
            for (const cal::FittedParam& p : r.params) {
                if (p.key != key) continue;
                line += p.at_fit.identifiable
                            ? fmt::format("  # fitted (start {:.6g}): interval [{:.6g}, {:.6g}] {}", p.start,
                                          p.at_fit.ci_lo, p.at_fit.ci_hi, p.unit)
                            : fmt::format("  # fitted (start {:.6g}), NOT pinned down: {}", p.start, p.at_fit.reason);
            }
            const std::string tie = cal::tied_to(key, fitted_keys);
            if (!tie.empty()) line += fmt::format("  # follows {} (fitted): one constant in SI units", tie);
        }
        out += line + "\n";
    }
    return out;
}

std::string log_names(const std::vector<cal::LogRun>& runs) {
    std::vector<std::string> names;
    names.reserve(runs.size());
    for (const auto& r : runs) {
        names.push_back(r.first == 0 && r.end == 0 ? r.log.source
                                                   : fmt::format("{} [{}, {})", r.log.source, r.first,
                                                                 r.end == 0 ? r.log.samples.size() : r.end));
    }
    return fmt::format("{}", fmt::join(names, ", "));
}

/// The predicted track of a whole log (all samples), averaged over the phases.
std::vector<std::pair<double, double>> track(const plant::RobotParams& p, const cal::RobotLog& log,
                                             const cal::ObjectiveConfig& objective) {
    cal::ObjectiveConfig o = objective;
    o.count_weight = 0.0;  // positions only
    const std::vector<double> y = cal::predicted_log(p, {log, 0, 0}, o);
    std::vector<std::pair<double, double>> out;
    for (std::size_t k = 0; k + 1 < y.size(); k += 2) out.emplace_back(y[k], y[k + 1]);
    return out;
}

std::string slug(const std::string& source, std::size_t index) {
    // A run's or scenario's folder names its uart.txt.
    const fs::path p(source);
    std::string s = p.filename() == "uart.txt" && p.has_parent_path() ? p.parent_path().filename().string() : p.stem().string();
    for (char& c : s) {
        if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') c = '_';
    }
    return fmt::format("{}_{}", index + 1, s);
}

std::string score_row(const char* what, const cal::SetScore& s) {
    return fmt::format("| {} | {:.1f} | {:.1f} | {:.1f} | {:.2f} |\n", what, s.rms_m * 1e3, s.max_m * 1e3,
                       s.endpoint_m * 1e3, s.endpoint_pct);
}

/// Refuses a log given twice (a held-out log that is also fitted, above all).
void check_logs_distinct(const CalibrateCli& o) {
    std::vector<std::string> given = o.logs;
    given.insert(given.end(), o.holdout.begin(), o.holdout.end());
    std::vector<fs::path> seen;
    for (std::size_t i = 0; i < given.size(); ++i) {
        const fs::path c = fs::weakly_canonical(log_file(given[i]));
        const auto first = std::find(seen.begin(), seen.end(), c);
        if (first != seen.end()) {
            const bool held_out = i >= o.logs.size() && static_cast<std::size_t>(first - seen.begin()) < o.logs.size();
            throw std::invalid_argument(fmt::format("{}: given twice{}", given[i],
                                                    held_out ? " (a held-out log must not be a fitted one)" : ""));
        }
        seen.push_back(c);
    }
}

/// Every log as long as its case's run (one sample per 0.1 s).
void check_log_lengths(const std::vector<cal::RobotLog>& all, int case_number) {
    // The simulation is as long as the dump; a cut dump (fewer lines than
    // the case logs) would be compared with the totals of the whole run.
    const auto expected = static_cast<std::size_t>(std::lround(hostsim::firmware_case(case_number).duration_s * 10.0));
    for (const cal::RobotLog& l : all) {
        if (l.samples.size() != expected) {
            throw std::invalid_argument(fmt::format("{}: {} logged samples; case {} logs {} (one per 0.1 s): is the dump "
                                                    "cut short?",
                                                    l.source, l.samples.size(), case_number, expected));
        }
    }
}

/// Removes what an earlier calibration left in `out` and this one would not replace.
void remove_stale_outputs(const fs::path& out) {
    for (const auto& e : fs::directory_iterator(out)) {
        const std::string name = e.path().filename().string();
        if ((name.rfind("xy_", 0) == 0 && e.path().extension() == ".svg") || (name == "hil" && e.is_directory())) {
            fs::remove_all(e.path());
        }
    }
}


/// tracks.csv's text and the plots of each log: logged, before and after.
struct Tracks {
    std::string csv;
    std::vector<std::pair<std::string, std::string>> plots;  // file, role
};

/// Writes each log's plot (xy_N_NAME.svg) in `out`; returns them with tracks.csv's text.
Tracks write_track_plots(const CalibrateCli& o, const cal::CalibrationSetup& setup, const cal::CalibrationResult& r,
                         const fs::path& out) {
    Tracks t;
    t.csv = "log,sample,logged_x_m,logged_y_m,before_x_m,before_y_m,after_x_m,after_y_m\n";
    const auto plot_log = [&](const cal::RobotLog& log, const std::string& role, std::size_t index) {
        const auto logged = cal::logged_positions(log);
        const auto before = track(setup.start, log, setup.objective);
        const auto after = track(r.fitted, log, setup.objective);
        for (std::size_t k = 0; k < logged.size(); ++k) {
            t.csv += fmt::format("{},{},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f}\n", csv_field(log.source), k, logged[k].first,
                               logged[k].second, before[k].first, before[k].second, after[k].first, after[k].second);
        }
        const std::string file = "xy_" + slug(log.source, index) + ".svg";
        write_file_atomic(out / file, svg_xy_plot(fmt::format("{} ({})", log.source, role),
                                                   {{"logged (EEPROM)", "#222222", false, true, logged},
                                                    {"before (starting plant)", "#d62728", true, false, before},
                                                    {"after (fitted plant)", "#1f77b4", false, false, after}}));
        t.plots.emplace_back(file, role);
    };
    std::size_t index = 0;
    for (const cal::RobotLog& l : setup.logs) plot_log(l, o.split ? "split: fitted, then judged" : "fitted", index++);
    for (const cal::RobotLog& l : setup.holdout_logs) plot_log(l, "held out", index++);
    return t;
}

/// calibration.json's list of fitted parameters.
nlohmann::json params_json(const std::vector<cal::FittedParam>& fitted) {
    nlohmann::json params = nlohmann::json::array();
    for (const cal::FittedParam& p : fitted) {
        params.push_back({{"key", p.key},
                          {"unit", p.unit},
                          {"start", p.start},
                          {"value", p.value},
                          {"search", {p.lo, p.hi}},
                          {"ci95", p.at_fit.identifiable ? nlohmann::json{p.at_fit.ci_lo, p.at_fit.ci_hi} : nlohmann::json(nullptr)},
                          {"relative_sd", std::isfinite(p.at_fit.relative_sd) ? nlohmann::json(p.at_fit.relative_sd)
                                                                               : nlohmann::json(nullptr)},
                          {"sensitivity_m", p.at_fit.sensitivity_m},
                          {"identifiable", p.at_fit.identifiable},
                          {"reason", p.at_fit.reason}});
    }
    return params;
}

/// The correlation matrix of the fitted parameters (null where undefined).
nlohmann::json correlation_json(const Eigen::MatrixXd& correlation) {
    nlohmann::json corr = nlohmann::json::array();
    for (Eigen::Index a = 0; a < correlation.rows(); ++a) {
        nlohmann::json row = nlohmann::json::array();
        for (Eigen::Index b = 0; b < correlation.cols(); ++b) {
            const double c = correlation(a, b);
            row.push_back(std::isfinite(c) ? nlohmann::json(c) : nlohmann::json(nullptr));
        }
        corr.push_back(row);
    }
    return corr;
}

/// The log parts of a set: each log with its first and end sample.
nlohmann::json names_json(const std::vector<cal::LogRun>& runs) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& run : runs) {
        a.push_back({{"log", run.log.source},
                     {"first", run.first},
                     {"end", run.end == 0 ? run.log.samples.size() : run.end}});
    }
    return a;
}

/// calibration.json, but its HIL confirmation.
nlohmann::json calibration_json(const CalibrateCli& o, const cal::CalibrationSetup& setup,
                                const cal::CalibrationResult& r, int case_number) {
    nlohmann::json j;
    j["case"] = case_number;
    j["seed"] = o.seed;
    j["split"] = o.split ? nlohmann::json(*o.split) : nlohmann::json(nullptr);
    j["start_plant"] = o.plant.empty() ? "defaults" : o.plant;
    j["encoder_phases"] = setup.objective.encoder_phases;
    j["period_s"] = setup.objective.base.period_s;
    j["logs"] = {{"train", names_json(r.train)}, {"holdout", r.holdout.empty() ? nlohmann::json(nullptr) : names_json(r.holdout)}};
    j["warnings"] = r.warnings;
    j["residual_rms_m"] = r.residual_rms_m;
    j["keys_chosen_by_data"] = o.fit_keys.empty();
    j["params"] = params_json(r.params);
    nlohmann::json not_fitted = nlohmann::json::array();
    for (const auto& [key, why] : r.not_fitted) not_fitted.push_back({{"key", key}, {"reason", why}});
    j["not_fitted"] = not_fitted;
    j["singular_values"] = r.identifiability.singular_values;
    j["correlation"] = correlation_json(r.identifiability.correlation);
    j["least_squares"] = {{"evaluations", r.least_squares.evaluations}, {"budget", o.lm_evaluations}, {"stop", r.least_squares.stop},
                          {"sum_of_squares_m2", r.least_squares.sum_of_squares}};
    j["fit"] = {{"evaluations", r.fit.evaluations}, {"loss", r.fit.loss}, {"global_loss", r.fit.global_loss},
                {"global_budget", o.global_evaluations}, {"local_budget", o.local_evaluations}};
    j["train"] = metrics_json(r.after_train);
    j["holdout"] = r.after_holdout ? metrics_json(*r.after_holdout) : nlohmann::json(nullptr);
    j["before"] = {{"train", metrics_json(r.before_train)},
                   {"holdout", r.before_holdout ? metrics_json(*r.before_holdout) : nlohmann::json(nullptr)}};
    return j;
}

/// plant.yaml's header: where the fit comes from, and how to use the file.
std::string plant_yaml_header(const CalibrateCli& o, const cal::CalibrationResult& r, int case_number) {
    return fmt::format(
        "# ddmr-hil calibrate: case {} from {}{}\n# start: {}; seed {}; load with --plant\n"
        "# intervals: 95 % under the log's quantisation, widened to what the host model cannot tell apart "
        "(docs/calibration.md)\n"
        "# every value without a comment is the starting plant's: the wheel radii and the axle cannot be "
        "calibrated from the firmware's log (measure them)\n", case_number,
        log_names(r.train), r.holdout.empty() ? "" : fmt::format(" (judged on {})", log_names(r.holdout)),
        o.plant.empty() ? "the embedded defaults" : o.plant, o.seed);
}

/// report.md: the parameters, the distances before and after, the HIL's, the plots.
std::string report_md(const cal::CalibrationResult& r, int case_number, const std::string& hil_md,
                      const std::vector<std::pair<std::string, std::string>>& plots) {
    std::string md = fmt::format("# Calibration: case {}\n\nFitted on {}.{}\n\n", case_number, log_names(r.train),
                                 r.holdout.empty() ? " Nothing was held out: the fit is not judged on unseen data."
                                                   : fmt::format(" Judged on {}.", log_names(r.holdout)));
    md += "## Parameters\n\n| parameter | start | fitted | 95 % interval | unit | pinned down |\n|---|---|---|---|---|---|\n";
    for (const cal::FittedParam& p : r.params) {
        md += fmt::format("| `{}` | {:.6g} | {:.6g} | {} | {} | {} |\n", p.key, p.start, p.value,
                          p.at_fit.identifiable ? fmt::format("[{:.6g}, {:.6g}]", p.at_fit.ci_lo, p.at_fit.ci_hi) : "—",
                          p.unit, p.at_fit.identifiable ? "yes" : "no: " + p.at_fit.reason);
    }
    if (!r.not_fitted.empty()) {
        md += "\nNot fitted (the logs cannot pin them down; they keep their start values):\n\n";
        for (const auto& [key, why] : r.not_fitted) md += fmt::format("- `{}`: {}\n", key, why);
    }
    if (!r.warnings.empty()) {
        md += "\n**Warnings:**\n\n";
        for (const std::string& w : r.warnings) md += "- " + w + "\n";
    }
    md += fmt::format("\nSingular values of the scaled sensitivity matrix: {:.3g}.\n",
                      fmt::join(r.identifiability.singular_values, ", "));
    md += "\n## Distance to the logs (host firmware model, mean over the encoder phases)\n\n"
          "Distances are to each logged sample's 4 mm cell (0 inside it).\n\n"
          "| plant, part | RMS [mm] | max [mm] | end [mm] | end [% of end vector] |\n|---|---|---|---|---|\n";
    md += score_row("before, fitted part", r.before_train);
    md += score_row("after, fitted part", r.after_train);
    if (r.after_holdout) {
        md += score_row("before, held out", *r.before_holdout);
        md += score_row("after, held out", *r.after_holdout);
    }
    md += "\n## The HIL with the real firmware on the fitted plant\n\n"
          "Distances between the decoded tracks of its own dump (`hil/uart.txt`) and each log. Both are "
          "quantised: tracks one cell apart are 4 mm apart.\n\n" + hil_md;
    md += "\n## Tracks\n\n";
    for (const auto& [file, role] : plots) md += fmt::format("![{}]({})\n\n", role, file);
    return md;
}

/// stdout: the parameters and the scores.
void print_calibration(const cal::CalibrationResult& r, int case_number) {
    std::printf("calibrate: case %d, %zu log part(s) fitted, %zu judged; %d + %d evaluations\n", case_number,
                r.train.size(), r.holdout.size(), r.least_squares.evaluations, r.fit.evaluations);
    for (const cal::FittedParam& p : r.params) {
        if (p.at_fit.identifiable) {
            std::printf("  %-40s %10.5g -> %-10.5g [%.5g, %.5g] %s\n", p.key.c_str(), p.start, p.value, p.at_fit.ci_lo,
                        p.at_fit.ci_hi, p.unit);
        } else {
            std::printf("  %-40s %10.5g -> %-10.5g not pinned down: %s\n", p.key.c_str(), p.start, p.value,
                        p.at_fit.reason.c_str());
        }
    }
    for (const auto& [key, why] : r.not_fitted) std::printf("  not fitted: %s: %s\n", key.c_str(), why.c_str());
    for (const std::string& w : r.warnings) std::printf("  warning: %s\n", w.c_str());
    std::printf("  fitted part: RMS %.1f mm -> %.1f mm\n", r.before_train.rms_m * 1e3, r.after_train.rms_m * 1e3);
    if (r.after_holdout) {
        std::printf("  held out:    RMS %.1f mm -> %.1f mm, end %.2f %% -> %.2f %%\n", r.before_holdout->rms_m * 1e3,
                    r.after_holdout->rms_m * 1e3, r.before_holdout->endpoint_pct, r.after_holdout->endpoint_pct);
    }
}

int run_calibrate(const CalibrateCli& o) {
    const auto wall_start = std::chrono::steady_clock::now();
    const auto say = [&](const std::string& line) {
        if (!o.quiet) std::fprintf(stderr, "calibrate: %s\n", line.c_str());
    };
    // Every input first: nothing is written before they are all good.
    if (o.seed < 0) throw std::invalid_argument(fmt::format("--seed {}: must be >= 0", o.seed));
    if (!(o.period_ms >= 0.1 && o.period_ms <= 1000.0)) {
        throw std::invalid_argument(fmt::format("--period-ms {}: must be in [0.1, 1000] ms", o.period_ms));
    }
    cal::CalibrationSetup setup;
    for (const std::string& f : o.logs) setup.logs.push_back(cal::read_robot_log(log_file(f)));
    for (const std::string& f : o.holdout) setup.holdout_logs.push_back(cal::read_robot_log(log_file(f)));
    if (o.split && !o.holdout.empty()) throw std::invalid_argument("--split and --hold-out: give one of them");
    std::vector<cal::RobotLog> all = setup.logs;
    all.insert(all.end(), setup.holdout_logs.begin(), setup.holdout_logs.end());
    check_logs_distinct(o);
    const int case_number = case_of(o, all);
    check_log_lengths(all, case_number);
    setup.split = o.split;
    if (!o.plant.empty()) setup.start = plant::load_robot_params(o.plant);
    setup.keys = o.fit_keys;
    setup.objective.base = hostsim::config_for_case(case_number, hostsim::Model::firmware);
    setup.objective.base.plant = setup.start;
    setup.objective.base.pwm = hostsim::PwmModel::switched;  // the robot's L298 sees the 490 Hz waveform
    setup.objective.base.period_s = o.period_ms * 1e-3;
    hostsim::validate(setup.objective.base);
    if (o.phases < 1 || o.phases > 64) throw std::invalid_argument(fmt::format("--phases {}: must be in [1, 64]", o.phases));
    setup.objective.encoder_phases.clear();
    for (int i = 0; i < o.phases; ++i) setup.objective.encoder_phases.push_back((i + 0.5) / o.phases);
    setup.least_squares.max_evaluations = o.lm_evaluations;
    setup.fit.seed = static_cast<uint64_t>(o.seed);
    setup.fit.global_evaluations = o.global_evaluations;
    setup.fit.local_evaluations = o.local_evaluations;
    setup.least_squares.progress = [&](int n, double best) {
        if (n % 25 == 0) say(fmt::format("least squares: evaluation {} of at most {}: sum of squares {:.4g} m^2", n,
                                         o.lm_evaluations, best));
    };
    const int budget = o.global_evaluations + o.local_evaluations;
    setup.fit.progress = [&](int n, double best) {
        if (n % 25 == 0) say(fmt::format("robust loss: evaluation {} of at most {}: best loss {:.5g}", n, budget, best));
    };
    setup.stage = say;
    const fs::path out(o.out);
    check_output_dir(out);  // created once the fit has run: a refused input writes nothing
    if (!o.no_hil) {
        if (!fs::is_regular_file(o.firmware)) {
            throw std::invalid_argument(fmt::format("--firmware {}: no such file (build it, or give --no-hil)", o.firmware));
        }
        // Read and checked now: a bad ELF is found before the fit, not after it.
        hil::ElfImage::read(o.firmware).require_mcu(hil::atmega328p_mcu());
    }
    // The logs' warnings (a dump without its unwritten last line), -q or not,
    // once every input is good: a refusal stays one line. calibration.json
    // and report.md list them with the fit's.
    for (const cal::RobotLog& l : all) {
        for (const std::string& w : l.warnings) std::fprintf(stderr, "ddmr-hil calibrate: warning: %s\n", w.c_str());
    }

    const cal::CalibrationResult r = cal::calibrate(setup);
    prepare_output_dir(out);
    remove_stale_outputs(out);

    // The tracks, for the plots and tracks.csv.
    say("tracks for the plots");
    const Tracks tracks = write_track_plots(o, setup, r, out);

    nlohmann::json j = calibration_json(o, setup, r, case_number);
    write_file_atomic(out / "plant.yaml", plant_yaml(r, plant_yaml_header(o, r, case_number)));

    // The HIL with the real firmware on the fitted plant.
    const HilConfirmation hil =
        confirm_in_hil(o.no_hil ? std::nullopt : std::optional<std::string>(o.firmware), all, case_number, out, say);
    j["hil"] = hil.json;
    write_file_atomic(out / "tracks.csv", tracks.csv);
    write_file_atomic(out / "calibration.json", j.dump(2) + "\n");

    write_file_atomic(out / "report.md", report_md(r, case_number, hil.md, tracks.plots));
    print_calibration(r, case_number);
    if (!hil.summary.empty()) std::printf("%s\n", hil.summary.c_str());
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    std::printf("  wrote %s/plant.yaml, calibration.json, report.md (%.0f s)\n", out.string().c_str(), wall_s);
    return hil.exit_code;
}

}  // namespace

Subcommand register_calibrate_command(CLI::App& app) {
    auto cli = std::make_shared<CalibrateCli>();
    CLI::App* sub = app.add_subcommand(
        "calibrate",
        "Fit plant parameters to a robot's serial dumps (the reference sketch's report and EEPROM dump), "
        "judge the fit on held-out data and confirm it in the HIL (docs/calibration.md)");
    sub->add_option("logs", cli->logs,
                    "The robot's serial dumps to fit (case 1: END, Count1, Count2, the EEPROM dump), or output "
                    "folders of `run` or `scenario` (their uart.txt)")
        ->required()
        ->check(CLI::ExistingPath);
    sub->add_option("--hold-out", cli->holdout, "A dump (or output folder) judged but not fitted (repeatable)")
        ->check(CLI::ExistingPath);
    sub->add_option("--split", cli->split, "Fit each log's first fraction F of the samples, judge the rest (0 < F < 1)");
    sub->add_option("--case", cli->case_number, "The case the logs ran (default: their banner; only case 1 logs a track)");
    sub->add_option("--fit", cli->fit_keys,
                    "Plant keys to fit, comma-separated (default: those the logs pin down among the motors', "
                    "the driver's and the battery's)")
        ->delimiter(',');
    sub->add_option("--plant", cli->plant, "The starting plant (a plant YAML; default: the embedded defaults)")
        ->check(CLI::ExistingFile);
    sub->add_option("--out", cli->out, "Output folder")->capture_default_str();
    sub->add_option("--seed", cli->seed, "The optimiser's seed (>= 0)")->capture_default_str();
    sub->add_option("--lm-evals", cli->lm_evaluations,
                    "Evaluations of the least-squares stage (Levenberg-Marquardt on the cells' centres)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    sub->add_option("--global-evals", cli->global_evaluations,
                    "Evaluations of a global search of the robust loss after it (CRS2; 0: none)")
        ->capture_default_str()
        ->check(CLI::Range(0, 100000));
    sub->add_option("--local-evals", cli->local_evaluations, "Evaluations of the robust loss's local polish (BOBYQA and its restarts)")
        ->capture_default_str()
        ->check(CLI::Range(1, 100000));
    sub->add_option("--phases", cli->phases, "Encoder phases each simulation is averaged over")->capture_default_str();
    sub->add_option("--period-ms", cli->period_ms,
                    "The firmware's loop period [ms] (10 ms of delay plus its computation: 10.44 on a 16 MHz Uno)")
        ->capture_default_str();
    sub->add_flag("--no-hil", cli->no_hil, "Skip the confirmation run in the HIL");
    sub->add_option("--firmware", cli->firmware, "The reference firmware's ELF for the HIL confirmation")->capture_default_str();
    sub->add_flag("-q,--quiet", cli->quiet, "No progress on stderr");
    return {sub, [cli] { return run_calibrate(*cli); }};
}

}  // namespace ddmr::tools
