// `ddmr-hil sweep [--study ID[,ID...]] [-j N] [--out DIR] [--model ideal|firmware]
//                 [--plant kinematic|FILE] [--no-plot] [--quiet] [--shard I/N]`
//
// Every option is checked, every run's configuration validated and the
// plotting interpreter probed before the output folder is touched; a bad
// value gives one line naming the option and the value, exit code 2. The
// files hold no wall time and are written in study order from results
// stored by index: -j 1 and -j 8 give the same bytes. With --shard I/N only
// the runs at positions I-1, I-1+N, ... of the whole sweep run, into a shard
// folder that `ddmr-hil merge` combines with the others into the unsharded
// sweep's files (tools/sweep_results.hpp).
#include "sweep_command.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/hostsim_json.hpp"
#include "common/plant_option.hpp"
#include "exit_codes.hpp"
#include "plant/params_yaml.hpp"
#include "scenario/suite_results.hpp"
#include "sweep_results.hpp"
#include "tools/hostsim/gain_sweep.hpp"

extern char** environ;

namespace ddmr::tools {

namespace {

namespace hs = ddmr::hostsim;

/// `--plant kinematic` selects the kinematic robot instead of a parameter file.
/// The interpreter the plots need (Debian's, with python3-matplotlib), as
/// the Makefile runs make_report.py.
constexpr const char* kPython = "/usr/bin/python3";

struct SweepCli {
    std::string studies = "all";
    unsigned jobs = 0;  ///< 0: one per hardware thread
    std::string out = "out/sweep";
    std::string model = "ideal";
    std::string plant;
    bool no_plot = false;
    bool quiet = false;
    std::string shard;  ///< "I/N", or empty: every run
};

/// Everything the sweep needs, checked.
struct SweepPlan {
    std::vector<hs::Study> studies;
    std::vector<hs::StudyRun> runs;        ///< every study's runs, study after study
    std::vector<std::size_t> study_of_run; ///< index into studies
    std::vector<hs::SimConfig> configs;    ///< one per run
    hs::SimConfig base;
    std::string plant_source;
    unsigned workers = 1;
    std::filesystem::path out_dir;
    std::optional<scenario::Shard> shard;  ///< only its runs, into a shard folder
};

SweepPlan plan_of(const SweepCli& o) {
    SweepPlan p;
    try {
        p.studies = hs::select_studies(o.studies);
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("--study {}: {}", o.studies, e.what()));
    }
    hs::SimConfig& b = p.base;
    b.model = hs::parse_model(o.model);
    b.fidelity = b.model == hs::Model::firmware ? hs::Fidelity::all() : hs::Fidelity::none();
    const PlantChoice plant_choice = resolve_plant_option(o.plant);
    b.kinematic_plant = plant_choice.kinematic;
    b.plant = plant_choice.params;
    p.plant_source = plant_choice.source;
    if (b.kinematic_plant && b.model != hs::Model::ideal) {
        throw std::invalid_argument("--plant kinematic: only with --model ideal");
    }
    b.plant_step_s = b.plant.stepper.max_step_s;

    for (std::size_t s = 0; s < p.studies.size(); ++s) {
        for (const hs::StudyRun& r : hs::study_runs(p.studies[s])) {
            p.runs.push_back(r);
            p.study_of_run.push_back(s);
            p.configs.push_back(hs::run_config(b, r));
            try {
                hs::validate(p.configs.back());
            } catch (const std::invalid_argument& e) {
                throw std::invalid_argument(fmt::format("--study {}, {} = {}: {}", p.studies[s].id,
                                                        hs::to_string(p.studies[s].varied), r.value, e.what()));
            }
        }
    }
    p.workers = o.jobs != 0 ? o.jobs : std::max(1u, std::thread::hardware_concurrency());
    p.out_dir = o.out;
    if (!o.shard.empty()) p.shard = scenario::parse_shard(o.shard);
    return p;
}

/// Runs `argv` (argv[0] an absolute path) without a shell and returns its
/// exit code (-1 if it could not start or was killed). quiet: stdout and
/// stderr to /dev/null.
int run_process(std::vector<std::string> argv, bool quiet) {
    std::vector<char*> args;
    args.reserve(argv.size() + 1);
    for (std::string& a : argv) args.push_back(a.data());
    args.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    if (quiet) {
        posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
        posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, "/dev/null", O_WRONLY, 0);
    }
    pid_t pid = 0;
    const int rc = posix_spawn(&pid, args[0], &actions, nullptr, args.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    if (rc != 0) return -1;
    int status = 0;
    if (waitpid(pid, &status, 0) != pid) return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// The plots need kPython with matplotlib and the script: checked before
/// anything is written (the script's --check only imports matplotlib).
void check_plotting() {
    const std::string script = hs::sweep_plot_script();
    if (::access(kPython, X_OK) != 0) {
        throw std::invalid_argument(fmt::format(
            "plots need {} with matplotlib (apt-get install python3-matplotlib), or pass --no-plot", kPython));
    }
    if (!std::filesystem::is_regular_file(script)) {
        throw std::invalid_argument(fmt::format("plot script {} is missing; pass --no-plot", script));
    }
    if (run_process({kPython, script, "--check"}, /*quiet=*/true) != 0) {
        throw std::invalid_argument(fmt::format(
            "{} cannot import matplotlib: apt-get install python3-matplotlib, or pass --no-plot", kPython));
    }
}



/// One run's rows of its study's CSV (kSweepCsvHeader), in long format: one
/// row per sample. gain_value is empty when the study varies no gain;
/// error_m = |G - P|; xe_m, ye_m = eq. (12)'s error in the robot frame (true pose).
std::string run_csv_rows(const hs::Study& study, const hs::StudyRun& run, const hs::SimResult& r) {
    std::string csv;
    const std::string gain = study.varied == hs::SweptGain::none ? "" : fmt::format("{:g}", run.value);
    for (const hs::SimSample& s : r.samples) {
        const hs::TrackingError<double> e =
            hs::tracking_error<double>(s.goal_x_m, s.goal_y_m, 0.0, {s.x_m, s.y_m, s.theta_rad});
        fmt::format_to(std::back_inserter(csv), "{},{},{:.2f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},{:.6f},"
                                                "{:.6f},{:.6f},{:.6f}\n",
                       run.case_spec.name, gain, s.t_s, s.x_m, s.y_m, s.theta_rad, s.goal_x_m, s.goal_y_m,
                       std::hypot(s.goal_x_m - s.x_m, s.goal_y_m - s.y_m), e.x_m, e.y_m, s.v_m_s, s.omega_rad_s);
    }
    return csv;
}

nlohmann::json run_json(const hs::Study& study, const hs::StudyRun& run, const hs::SimResult& r) {
    const hs::TrackingMetrics m = hs::tracking_metrics(r, run.case_spec);
    nlohmann::json j;
    j["case"] = run.case_spec.name;
    if (study.varied != hs::SweptGain::none) j[hs::to_string(study.varied)] = run.value;
    j["gains"] = gains_json(run.gains);
    j["gains_effective"] = gains_json(r.effective_gains);
    j["final_error_m"] = m.final_error_m;
    // eq. (12) at the end: the error along and across the robot's heading.
    const hs::SimSample& end = r.samples.back();
    const hs::TrackingError<double> e =
        hs::tracking_error<double>(end.goal_x_m, end.goal_y_m, 0.0, {end.x_m, end.y_m, end.theta_rad});
    j["final_xe_m"] = e.x_m;
    j["final_ye_m"] = e.y_m;
    j["rms_error_m"] = m.rms_error_m;
    j["max_error_m"] = m.max_error_m;
    j["settling_time_s"] = m.settling_time_s ? nlohmann::json(*m.settling_time_s) : nlohmann::json(nullptr);
    j["end_pose"] = {{"x_m", r.end_pose.x_m}, {"y_m", r.end_pose.y_m}, {"theta_rad", r.end_pose.theta_rad}};
    j["goal_end"] = {{"x_m", r.goal_end_x_m}, {"y_m", r.goal_end_y_m}};
    j["status"] = plant::to_string(r.status);
    if (r.status != plant::StepStatus::ok) j["status_at_s"] = r.status_at_s;
    return j;
}

/// sweep.json without the runs: the settings and every study, each with
/// "runs" empty (write_sweep_folder fills them).
nlohmann::json header_json(const SweepPlan& plan) {
    nlohmann::json j;
    j["model"] = hs::to_string(plan.base.model);
    j["fidelity"] = plan.base.fidelity.names();
    j["plant"] = plan.plant_source;
    j["pwm"] = hs::to_string(plan.base.pwm);
    j["plant_step_s"] = plan.base.plant_step_s;
    j["sample_period_s"] = hs::kSweepSamplePeriod_s;
    j["settle_band_m"] = hs::kSettleBand_m;
    j["studies"] = nlohmann::json::array();
    for (const hs::Study& study : plan.studies) {
        nlohmann::json js;
        js["id"] = study.id;
        js["figure"] = study.figure;
        js["title"] = study.title;
        js["csv"] = study.id + ".csv";
        js["varied"] = hs::to_string(study.varied);
        js["values"] = study.values;
        js["fixed_gains"] = gains_json(study.fixed);
        if (study.goal_feedforward) {
            js["fixed_gains"]["vref_m_s"] = "goal";
            js["fixed_gains"]["wref_rad_s"] = "goal";
        }
        js["trajectories"] = nlohmann::json::array();
        for (const hs::CaseSpec& c : study.trajectories) js["trajectories"].push_back(case_json(c));
        js["runs"] = nlohmann::json::array();
        j["studies"].push_back(js);
    }
    return j;
}

int run_sweep(const SweepCli& o) {
    const SweepPlan plan = plan_of(o);
    const bool plot = !o.no_plot && !plan.shard;  // a shard has no study CSVs to plot
    if (plot) check_plotting();
    prepare_output_dir(plan.out_dir);

    // The runs this process simulates: every run, or the shard's slice.
    std::vector<std::size_t> mine;
    std::vector<hs::SimConfig> configs;
    for (std::size_t k = 0; k < plan.runs.size(); ++k) {
        if (plan.shard && !plan.shard->contains(k)) continue;
        mine.push_back(k);
        configs.push_back(plan.configs[k]);
    }
    // Progress: a study is done when its last run is.
    std::vector<std::size_t> remaining(plan.studies.size(), 0);
    for (std::size_t k : mine) ++remaining[plan.study_of_run[k]];
    const auto studies_here = static_cast<std::size_t>(
        std::count_if(remaining.begin(), remaining.end(), [](std::size_t n) { return n > 0; }));
    std::size_t studies_done = 0;
    auto on_done = [&](std::size_t i) {
        const std::size_t s = plan.study_of_run[mine[i]];
        if (--remaining[s] != 0) return;
        ++studies_done;
        if (!o.quiet) {
            fmt::print(stderr, "sweep: {} done ({}/{} studies)\n", plan.studies[s].id, studies_done, studies_here);
        }
    };
    const auto wall_start = std::chrono::steady_clock::now();
    const std::vector<hs::SimResult> results = hs::simulate_parallel(configs, plan.workers, on_done);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    std::vector<SweepRunRecord> records;
    for (std::size_t i = 0; i < mine.size(); ++i) {
        const std::size_t k = mine[i];
        const hs::Study& study = plan.studies[plan.study_of_run[k]];
        records.push_back({plan.study_of_run[k], run_json(study, plan.runs[k], results[i]),
                           run_csv_rows(study, plan.runs[k], results[i])});
    }
    const nlohmann::json header = header_json(plan);
    if (plan.shard) {
        std::vector<const SweepRunRecord*> by_run(plan.runs.size(), nullptr);
        for (std::size_t i = 0; i < mine.size(); ++i) by_run[mine[i]] = &records[i];
        write_sweep_shard(plan.out_dir, {*plan.shard, header, plan.study_of_run}, by_run);
    } else {
        write_sweep_folder(plan.out_dir, header, records);
    }
    fmt::print("sweep: {}{} studies, {} runs, {} worker{}, wall {:.2f} s (simulation), wrote {}\n",
               plan.shard ? "shard " + plan.shard->text() + " of " : "", plan.studies.size(), mine.size(),
               std::min<std::size_t>(plan.workers, mine.size()), plan.workers == 1 ? "" : "s", wall_s,
               plan.out_dir.string());

    if (plot) {
        const int rc = run_process({kPython, hs::sweep_plot_script(), plan.out_dir.string()}, /*quiet=*/false);
        if (rc != 0) {
            fmt::print(stderr, "ddmr-hil sweep: plot_sweep.py failed (exit {}); the CSVs and sweep.json are in {}\n",
                       rc, plan.out_dir.string());
            return kExitCheckFailed;
        }
    }
    if (std::any_of(records.begin(), records.end(), stopped_early)) {
        fmt::print(stderr, "ddmr-hil sweep: a plant stopped early in some runs (status in sweep.json)\n");
        return kExitCheckFailed;
    }
    return kExitOk;
}

}  // namespace

Subcommand register_sweep_command(CLI::App& app) {
    auto o = std::make_shared<SweepCli>();
    CLI::App* sub = app.add_subcommand(
        "sweep", "The thesis's gain sensitivity studies (figs. 5-2 to 5-8, appendix A2) on the host simulation, "
                 "in parallel; CSVs, sweep.json and plots (docs/hostsim.md, Sweep)");
    std::string ids;
    for (const hs::Study& s : hs::thesis_studies()) ids += (ids.empty() ? "" : ", ") + s.id;
    sub->add_option("--study", o->studies, "studies to run, comma-separated (" + ids + "; or all)")
        ->capture_default_str();
    sub->add_option("-j,--jobs", o->jobs, "worker threads [default: one per hardware thread]")
        ->check(CLI::Range(1u, 1024u));
    sub->add_option("--out", o->out, "output folder")->capture_default_str();
    sub->add_option("--model", o->model, "ideal (the thesis's MATLAB idealisation) or firmware (every switch on)")
        ->check(CLI::IsMember({"ideal", "firmware"}))
        ->capture_default_str();
    sub->add_option("--plant", o->plant, "plant parameter YAML (default: embedded), or 'kinematic' (ideal only)");
    sub->add_flag("--no-plot", o->no_plot, "write the CSVs and sweep.json only (no python3-matplotlib needed)");
    sub->add_flag("-q,--quiet", o->quiet, "no progress on stderr");
    sub->add_option("--shard", o->shard,
                    "I/N: run only the I-th of N round-robin slices of the sweep's runs (positions I-1, I-1+N, ...), "
                    "into a shard folder without plots; `ddmr-hil merge` combines the N folders into the unsharded "
                    "sweep's files (docs/scaling.md)");
    return Subcommand{sub, [o] { return run_sweep(*o); }};
}

}  // namespace ddmr::tools
