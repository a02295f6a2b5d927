#pragma once
// The thesis's gain sensitivity studies (ch. 5, figs. 5-2 to 5-8, and
// appendix A2) as data, and a parallel runner for many SimConfigs.
//
//   Study (id, trajectory, the gain that varies, its values, the others fixed)
//     -> study_runs(): one StudyRun per (trajectory, value)
//     -> run_config(): a SimConfig for the run on a base (model, plant, PWM)
//     -> simulate_parallel(): SimResults in the order of the configs
//     -> tracking_metrics(): final / RMS / max error, settling time
//
// The studies (docs/hostsim.md, "Sweep", has the table):
//   A2 group 1 (figs. 5-2 to 5-4): the line at 0.5 m/s with a 20 cm step at
//     10 s, v_g = 0.5 m/s, w_g = 0, one gain varied over A2's values with the
//     other two zero: K_x on the step in X, K_y and K_w on the step in Y.
//   A2 group 2: the 1 m, 20 s circle, v_g = w_g = 0.3 (A2's values; the
//     goal's own are 0.314 m/s, 0.314 rad/s), one gain varied, the others zero.
//   A2 group 3 (figs. 5-5, 5-6): the same circle, K_x in 0.5 .. 2 with
//     K_y = 5, K_w = 0, then K_y = 0, K_w = 5.
//   Fig. 5-7: the same circle, K_w varied with K_x = 1, K_y = 6.
//   Fig. 5-8: K = (2, 12, 18) on two circles, 0.4 m in 8 s and 0.6 m in 12 s,
//     v_g, w_g = the goal's own velocity (the thesis does not state them).
//
// Deterministic: each run is a pure function of its SimConfig (simulate has
// no global state), and results are stored by index, so the output never
// depends on the number of workers or on scheduling.

#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "tools/hostsim/goal_trajectory.hpp"
#include "tools/hostsim/host_sim.hpp"
#include "tools/hostsim/kanayama.hpp"

namespace ddmr::hostsim {

/// Which of the three gains a study varies.
enum class SweptGain { kx, ky, kw, none };
/// "kx", "ky", "kw", "none".
const char* to_string(SweptGain g);

/// One sensitivity study: every trajectory run once per value of `varied`.
struct Study {
    std::string id;                    ///< "fig5_2", ... (file names: <id>.csv, <id>.png)
    std::string figure;                ///< where the thesis shows it: "Figure 5-2", "Appendix A2"
    std::string title;                 ///< what the figure shows, with the fixed gains
    std::vector<CaseSpec> trajectories;  ///< one, or several (fig. 5-8) run with the same gains
    SweptGain varied = SweptGain::none;
    std::vector<double> values;        ///< values of `varied` (empty when none)
    Gains fixed{};                     ///< every gain; the varied one is overwritten per run
    /// v_g, w_g = each trajectory's own velocity (goal_velocity) instead of
    /// fixed's: the thesis states none for fig. 5-8.
    bool goal_feedforward = false;
};

/// The thesis's studies, in figure order: fig5_2, fig5_3, fig5_4,
/// a2_circle_kx, a2_circle_ky, a2_circle_kw, fig5_5, fig5_6, fig5_7, fig5_8.
const std::vector<Study>& thesis_studies();

/// The studies named in a comma-separated list of ids, in the list's order,
/// duplicates dropped; "all" or "" = every study. Throws
/// std::invalid_argument naming the unknown id and the known ones.
std::vector<Study> select_studies(const std::string& ids);

/// One simulation of a study.
struct StudyRun {
    CaseSpec case_spec;        ///< the trajectory
    double value = 0.0;        ///< the varied gain's value (0 when none)
    Gains gains{};             ///< fixed, with the varied gain set to `value`
};

/// Trajectory-major: for each trajectory, each value in order.
std::vector<StudyRun> study_runs(const Study& s);

/// `base` (model, fidelity, plant, PWM, plant step) with the run's case,
/// gains and the case's duration, sampled every kSweepSamplePeriod_s.
SimConfig run_config(const SimConfig& base, const StudyRun& run);

/// Sample interval of the sweep's runs [s]: 100 Hz, enough for 20 s plots
/// (2001 rows a run) and for the settling time's resolution.
inline constexpr double kSweepSamplePeriod_s = 0.01;

/// Runs simulate() on every config with `workers` threads (0: one per
/// hardware thread; at most one per config). results[i] belongs to
/// configs[i] whatever the scheduling. Every config is validated before any
/// thread starts (std::invalid_argument naming the index and the problem).
/// `on_done(i)` is called after configs[i] finishes, one call at a time
/// (serialised by the runner), from a worker thread.
std::vector<SimResult> simulate_parallel(const std::vector<SimConfig>& configs, unsigned workers,
                                         const std::function<void(std::size_t)>& on_done = {});

/// Band of the settling time [m]: 2 cm, a tenth of A2's 20 cm step.
inline constexpr double kSettleBand_m = 0.02;

/// How well one run tracks, from its samples. The tracking error is the
/// distance |G - P| between the goal and the robot's true position [m].
struct TrackingMetrics {
    double final_error_m = 0.0;  ///< at the last sample
    double rms_error_m = 0.0;    ///< over every sample (equally spaced) of the run
    double max_error_m = 0.0;    ///< over every sample of the run
    /// Settling time [s], from the disturbance (the step at step_time_s on the
    /// line, t = 0 on a circle) to the first sample after which the error
    /// stays within band_m until the end; nullopt if the last sample is
    /// outside the band (not settled by the end of the run).
    std::optional<double> settling_time_s;
};

/// Metrics of `r`, a run of case `c`. Requires at least one sample.
TrackingMetrics tracking_metrics(const SimResult& r, const CaseSpec& c, double band_m = kSettleBand_m);

/// The script that plots a sweep's folder (tools/report/plot_sweep.py in
/// the source tree, its path fixed at configure time).
std::string sweep_plot_script();

}  // namespace ddmr::hostsim
