#pragma once
// The signals a scenario reads by name on its running robot (wait-until,
// expect, measure, expect-stats; docs/scenarios.md, "Signals"):
//   - the plant's (plant_signals.cpp: x_m, ..., left.wheel_rad_s);
//   - the world's and the parts' truth columns (RobotRig::extra_truth_columns:
//     line_offset_m, wall_distance_m, sonar.distance_m, ...);
// and the statistics of those a `measure` step started, one sample per
// truth sample (1 ms).

#include <map>
#include <string>
#include <vector>

#include "hil/robot_rig.hpp"
#include "scenario/scenario.hpp"

namespace ddmr::tools::scenario {

/// The robot a scenario runs: its plant, board, world, PWM and EEPROM
/// timing, serial port.
hil::RigConfig rig_config_of(const Scenario& s);

/// Refuses (ScenarioError, FILE:LINE) a step naming a signal the scenario's
/// robot does not have, before anything runs: the robot is built (not run)
/// when a step names a world or part signal.
void check_signal_names(const Scenario& s);

class RigSignals {
public:
    explicit RigSignals(hil::RobotRig& rig);

    /// Throws ScenarioError "FILE:LINE: key 'signal': ..." for each step of
    /// `s` naming a signal this robot does not have (a part's column its
    /// options do not give, a world column without a world).
    void check_steps(const Scenario& s) const;

    /// The signal's value now (the AVR's cycle).
    [[nodiscard]] double now(const std::string& name) const;

    /// Starts (or restarts) the statistics of `name`.
    void measure(const std::string& name);
    /// One truth sample: each measured signal's value goes into its statistics.
    void on_truth(const hil::TruthSample& sample);
    /// Checks `e` against the statistics; throws StepFailed when a bound does
    /// not hold; returns what was measured.
    [[nodiscard]] std::string expect_stats(const ExpectStats& e) const;

private:
    struct Stats {
        uint64_t n = 0;
        double sum = 0.0, sum_sq = 0.0, min = 0.0, max = 0.0;
    };
    [[nodiscard]] bool has(const std::string& name) const;
    /// The position of a world or part signal in extra_ (checked: present).
    [[nodiscard]] std::size_t extra_index(const std::string& name) const;

    hil::RobotRig& rig_;
    std::vector<std::string> extra_;  ///< RobotRig::extra_truth_columns()
    mutable std::vector<double> values_;
    std::map<std::string, Stats> stats_;
};

}  // namespace ddmr::tools::scenario
