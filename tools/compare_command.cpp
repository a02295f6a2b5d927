// `ddmr-hil compare RUN_DIR [--sim ideal|firmware] [--tolerance-m X]`
//
// Time base: the firmware's log, one sample every 10 control iterations.
// Case 1: the EEPROM log (eeprom_log.csv, t_s since the case byte); case 2
// logs no EEPROM, so its samples are the firmware's own Ex, Ey at every 10th
// iteration (firmware.csv). For each sample k:
//   log   : the firmware's logged position (what the robot believed);
//   truth : the HIL plant's position at the same AVR time (truth.csv);
//   sim   : the host simulation's true position after the same number of
//           control iterations, 10 (k + 1) periods into its run.
// Aligning the simulation by iteration rather than by seconds keeps the
// comparison about the control loop: the HIL's real period is ~10.4 ms, the
// sketch assumes 10 ms; the difference in seconds is the loop-timing effect
// only the HIL has (see summary.json's mean_loop_period_s).
//
// Pairs: log_vs_truth, log_vs_sim, truth_vs_sim (reference second); and,
// when the simulation writes the sketch's EEPROM log too (the firmware
// model), log_vs_sim_log: the two logs byte-decoded, sample by sample, where
// the firmware's own dead-reckoning error cancels and what remains is the
// timing only the HIL has. The check: log_vs_sim rms_m <= --tolerance-m.
// Attribution: the ideal model, then the ideal model with each fidelity
// switch on alone, then all switches (the firmware model), each against the
// log: the change in endpoint and RMS error from the ideal baseline.
#include "compare_command.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/output_folder.hpp"
#include "common/sim_csv.hpp"
#include "comparison.hpp"
#include "common/shell_quote.hpp"
#include "exit_codes.hpp"
#include "common/csv_table.hpp"
#include "plant/params_yaml.hpp"
#include "tools/hostsim/host_sim.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
namespace hs = ddmr::hostsim;
using nlohmann::json;

constexpr int kIterationsPerSample = kIterationsPerLogSample;

struct CompareCli {
    std::string run_dir;
    std::string sim = "firmware";
    double tolerance_m = 0.05;
};

/// The firmware's logged track and the HIL times of its samples.
struct LoggedTrack {
    std::vector<Point2> points;
    std::vector<double> t_since_case_s;
    std::string source;
};

LoggedTrack logged_track(const fs::path& dir, const json& summary) {
    LoggedTrack track;
    const double clock_hz = summary.at("clock_hz").get<double>();
    const double ready_s = summary.at("ready_cycle").is_null() ? 0.0 : summary["ready_cycle"].get<double>() / clock_hz;
    if (summary.at("eeprom_log_samples").get<int>() > 0) {
        const auto p = dir / "eeprom_log.csv";
        const Table t = read_table(p);
        for (std::size_t k = 0; k < t.rows(); ++k) {
            track.points.push_back({t.col("x_m", p)[k], t.col("y_m", p)[k]});
            track.t_since_case_s.push_back(t.col("t_s", p)[k]);
        }
        track.source = "eeprom_log.csv";
    } else {
        const auto p = dir / "firmware.csv";
        const Table t = read_table(p);
        const auto& tv = t.col("t", p);
        int iteration = 0;
        double last_t = 0.0;
        for (std::size_t r = 0; r < t.rows(); ++r) {
            if (!(tv[r] > last_t)) break;  // the sketch resets t after its report
            last_t = tv[r];
            if (++iteration % kIterationsPerSample != 0) continue;
            track.points.push_back({t.col("Ex", p)[r], t.col("Ey", p)[r]});
            track.t_since_case_s.push_back(t.col("t_avr_s", p)[r] - ready_s);
        }
        track.source = "firmware.csv (every 10th iteration)";
    }
    if (track.points.empty()) throw std::runtime_error(dir.string() + ": the run has no logged samples to compare");
    return track;
}

json metrics_json(const PairMetrics& m) {
    return {{"rms_m", m.rms_m}, {"max_m", m.max_m}, {"endpoint_m", m.endpoint_m},
            {"endpoint_pct", m.endpoint_pct}, {"samples", m.samples}};
}

int run_compare(const CompareCli& cli) {
    const fs::path dir = cli.run_dir;
    if (!(cli.tolerance_m > 0.0) || !std::isfinite(cli.tolerance_m)) {
        throw std::invalid_argument(fmt::format("--tolerance-m {}: must be a positive distance in metres", cli.tolerance_m));
    }
    const FolderKind kind = folder_kind(dir);
    if (kind != FolderKind::run) {
        throw std::runtime_error(fmt::format("{}: {}; compare takes the output folder of `ddmr-hil run` (summary.json, "
                                             "truth.csv, eeprom_log.csv) and runs the simulation itself",
                                             dir.string(), describe(kind)));
    }
    json summary;
    {
        std::ifstream in(dir / "summary.json");
        try {
            summary = json::parse(in);
        } catch (const json::exception& e) {
            throw std::runtime_error((dir / "summary.json").string() + ": malformed JSON: " + e.what());
        }
    }
    // The fields compare reads, each with its type: a summary written by
    // another version, or edited, is one line naming the field.
    const auto require = [&](const char* key, bool ok, const char* what) {
        if (!ok) {
            throw std::runtime_error(fmt::format("{}: \"{}\" is not {} as `ddmr-hil run` writes it", (dir / "summary.json").string(),
                                                 key, what));
        }
    };
    require("case", summary.contains("case") && (summary["case"].is_number_integer() || summary["case"].is_null()),
            "a case number");
    if (summary["case"].is_null()) {
        throw std::runtime_error(fmt::format("{}: the run had no case (a firmware without a contract); compare needs a "
                                             "run of the reference firmware's case 1 or 2",
                                             dir.string()));
    }
    require("clock_hz", summary.contains("clock_hz") && summary["clock_hz"].is_number(), "a number");
    require("ready_cycle", summary.contains("ready_cycle") && (summary["ready_cycle"].is_number() || summary["ready_cycle"].is_null()),
            "a cycle count");
    require("eeprom_log_samples", summary.contains("eeprom_log_samples") && summary["eeprom_log_samples"].is_number_integer(),
            "a sample count");
    const int test_case = summary.at("case").get<int>();
    const LoggedTrack log = logged_track(dir, summary);
    const auto truth_path = dir / "truth.csv";
    const Table truth = read_table(truth_path);
    const double clock_hz = summary.at("clock_hz").get<double>();
    const double ready_s = summary.at("ready_cycle").is_null() ? 0.0 : summary["ready_cycle"].get<double>() / clock_hz;
    std::vector<Point2> truth_track;
    for (const double t : log.t_since_case_s) {
        truth_track.push_back(interpolate(truth.col("t_s", truth_path), truth.col("x_m", truth_path),
                                          truth.col("y_m", truth_path), ready_s + t));
    }

    // The simulation of the same robot: same case, plant file and PWM model.
    const hs::Model model = hs::parse_model(cli.sim);
    hs::SimConfig base = hs::config_for_case(test_case, hs::Model::ideal);
    const std::string plant_file = summary.value("plant_file", std::string("(embedded defaults)"));
    if (plant_file != "(embedded defaults)") base.plant = plant::load_robot_params(plant_file);
    base.pwm = summary.value("pwm", std::string("switched")) == "switched" ? hs::PwmModel::switched
                                                                          : hs::PwmModel::averaged;
    // Long enough for every logged sample's iteration count.
    base.duration_s = std::max(base.duration_s, static_cast<double>(kIterationsPerSample * log.points.size()) * base.period_s + 0.05);
    const auto run_with = [&](const hs::Fidelity& f) {
        hs::SimConfig c = base;
        c.fidelity = f;
        c.model = f.is_all() ? hs::Model::firmware : hs::Model::ideal;
        hs::validate(c);
        return std::make_pair(c, hs::simulate(c));
    };
    const auto [chosen_config, chosen] = run_with(model == hs::Model::firmware ? hs::Fidelity::all() : hs::Fidelity::none());
    const std::vector<Point2> sim = sim_track(chosen, chosen_config, log.points.size());

    const PairMetrics log_truth = compare_tracks(log.points, truth_track);
    const PairMetrics log_sim = compare_tracks(log.points, sim);
    const PairMetrics truth_sim = compare_tracks(truth_track, sim);
    std::optional<PairMetrics> log_sim_log;
    if (chosen.eeprom_logged && chosen.eeprom_log.size() == log.points.size() &&
        log.source == "eeprom_log.csv") {
        std::vector<Point2> sim_log;
        for (const auto& e : chosen.eeprom_log) sim_log.push_back({e.x_m, e.y_m});
        log_sim_log = compare_tracks(log.points, sim_log);
    }

    json attribution = json::array();
    const auto [ideal_config, ideal] = run_with(hs::Fidelity::none());
    const PairMetrics ideal_m = compare_tracks(log.points, sim_track(ideal, ideal_config, log.points.size()));
    const auto attribute = [&](const std::string& name, const hs::Fidelity& f) {
        const auto [c, r] = run_with(f);
        const PairMetrics m = compare_tracks(log.points, sim_track(r, c, log.points.size()));
        attribution.push_back({{"switch", name},
                               {"endpoint_m", m.endpoint_m},
                               {"rms_m", m.rms_m},
                               {"endpoint_change_m", m.endpoint_m - ideal_m.endpoint_m},
                               {"rms_change_m", m.rms_m - ideal_m.rms_m}});
    };
    for (const char* name : hs::fidelity_switch_names()) attribute(name, hs::Fidelity::parse(name));
    attribute("all (firmware model)", hs::Fidelity::all());

    // The `sim` command line that writes the same sim.csv (the same case,
    // model, plant, PWM model and duration; the period is sim's default).
    std::string sim_command = fmt::format("ddmr-hil sim --model {} --case {} --pwm {} --duration {:.2f}", hs::to_string(model),
                                          test_case, hs::to_string(base.pwm), base.duration_s);
    if (plant_file != "(embedded defaults)") sim_command += " --plant " + shell_quote(plant_file);
    sim_command += " --out " + shell_quote((dir / "sim-reproduced").string());
    const bool pass = log_sim.rms_m <= cli.tolerance_m;
    json out = {
        {"run_dir", dir.string()},
        {"case", test_case},
        {"sim_model", hs::to_string(model)},
        {"time_base", {{"source", log.source},
                       {"samples", log.points.size()},
                       {"iterations_per_sample", kIterationsPerSample},
                       {"sim_period_s", base.period_s}}},
        {"pairs", {{"log_vs_truth", metrics_json(log_truth)},
                   {"log_vs_sim", metrics_json(log_sim)},
                   {"truth_vs_sim", metrics_json(truth_sim)}}},
        {"ideal_baseline", metrics_json(ideal_m)},
        {"attribution", attribution},
        {"sim_command", sim_command},
        {"tolerance_m", cli.tolerance_m},
        {"check", "log_vs_sim.rms_m <= tolerance_m"},
        {"pass", pass},
    };
    if (log_sim_log) out["pairs"]["log_vs_sim_log"] = metrics_json(*log_sim_log);
    write_file_atomic(dir / "sim.csv", sim_csv(chosen));
    write_file_atomic(dir / "compare.json", out.dump(2) + "\n");

    std::printf("%-14s %9s %9s %12s %12s\n", "pair", "rms [m]", "max [m]", "endpoint [m]", "endpoint [%]");
    std::vector<std::pair<const char*, PairMetrics>> rows = {
        {"log_vs_truth", log_truth}, {"log_vs_sim", log_sim}, {"truth_vs_sim", truth_sim}};
    if (log_sim_log) rows.emplace_back("log_vs_sim_log", *log_sim_log);
    for (const auto& [name, m] : rows) {
        std::printf("%-14s %9.4f %9.4f %12.4f %12.2f\n", name, m.rms_m, m.max_m, m.endpoint_m, m.endpoint_pct);
    }
    std::printf("\nattribution against the log (ideal %s: endpoint %.4f m, rms %.4f m):\n", "baseline",
                ideal_m.endpoint_m, ideal_m.rms_m);
    for (const auto& row : attribution) {
        std::printf("  %-22s endpoint %+.4f m   rms %+.4f m\n", row["switch"].get<std::string>().c_str(),
                    row["endpoint_change_m"].get<double>(), row["rms_change_m"].get<double>());
    }
    std::printf("\nthe simulation (sim.csv), reproduced: %s\n", sim_command.c_str());
    std::printf("plots of the run and this comparison (xy.png: truth, log and simulation): ddmr-hil report %s\n",
                shell_quote(dir.string()).c_str());
    std::printf("\n%s: log vs %s simulation rms %.4f m %s tolerance %.4f m; wrote %s\n", pass ? "PASS" : "FAIL",
                hs::to_string(model), log_sim.rms_m, pass ? "<=" : ">", cli.tolerance_m,
                (dir / "compare.json").string().c_str());
    return pass ? kExitOk : kExitCheckFailed;
}

}  // namespace

Subcommand register_compare_command(CLI::App& app) {
    auto cli = std::make_shared<CompareCli>();
    CLI::App* sub = app.add_subcommand(
        "compare",
        "Compare a run's firmware log and plant truth with the host simulation of the same robot; "
        "writes compare.json and sim.csv into the run folder. Exit 0 within tolerance, 1 not, 2 on error.");
    sub->add_option("RUN_DIR", cli->run_dir, "A folder written by `ddmr-hil run`")->required();
    sub->add_option("--sim", cli->sim, "Host simulation model: ideal or firmware")
        ->check(CLI::IsMember({"ideal", "firmware"}))
        ->capture_default_str();
    sub->add_option("--tolerance-m", cli->tolerance_m,
                    "Largest RMS distance between the firmware's log and the simulation [m]")
        ->capture_default_str();
    return Subcommand{sub, [cli]() {
        try {
            return run_compare(*cli);
        } catch (const json::exception& e) {
            // A field of the right name and the wrong shape: one line, not the library's code.
            throw std::runtime_error(fmt::format("{}: summary.json is not as `ddmr-hil run` writes it ({})",
                                                 cli->run_dir, e.what()));
        }
    }};
}

}  // namespace ddmr::tools
