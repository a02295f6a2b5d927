#include "tools/hostsim/gain_sweep.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "plant/units.hpp"

namespace ddmr::hostsim {
namespace {

const Study& study(const std::string& id) {
    for (const Study& s : thesis_studies()) {
        if (s.id == id) return s;
    }
    throw std::invalid_argument("no study " + id);
}

/// The ideal model on the kinematic robot: the plant of Kanayama's proof,
/// where eq. (14)'s (v, w) is the robot's velocity at once.
SimConfig kinematic_base() {
    SimConfig b;
    b.model = Model::ideal;
    b.fidelity = Fidelity::none();
    b.kinematic_plant = true;
    return b;
}

std::vector<SimResult> run_study(const Study& s, const SimConfig& base) {
    std::vector<SimConfig> configs;
    for (const StudyRun& r : study_runs(s)) configs.push_back(run_config(base, r));
    return simulate_parallel(configs, 2);
}

/// The sample at t_s (the sweep samples every 10 ms from 0).
const SimSample& at(const SimResult& r, double t_s) {
    const auto i = static_cast<std::size_t>(std::lround(t_s / kSweepSamplePeriod_s));
    EXPECT_NEAR(r.samples.at(i).t_s, t_s, 1e-9);
    return r.samples.at(i);
}

void expect_gains(const Gains& g, double kx, double ky, double kw, double vref, double wref) {
    EXPECT_EQ(g.kx, kx);
    EXPECT_EQ(g.ky, ky);
    EXPECT_EQ(g.kw, kw);
    EXPECT_EQ(g.vref_m_s, vref);
    EXPECT_EQ(g.wref_rad_s, wref);
}

// Appendix A2 and figs. 5-2 to 5-8, read off the thesis: trajectory, the
// varied gain and its values, the other gains and the feed-forward.
TEST(GainSweep, StudiesMatchAppendixA2AndChapter5) {
    std::vector<std::string> ids;
    for (const Study& s : thesis_studies()) ids.push_back(s.id);
    EXPECT_EQ(ids, (std::vector<std::string>{"fig5_2", "fig5_3", "fig5_4", "a2_circle_kx", "a2_circle_ky",
                                             "a2_circle_kw", "fig5_5", "fig5_6", "fig5_7", "fig5_8"}));

    // Group 1: the line at 0.5 m/s, 20 cm step at 10 s, 20 s; "Ky = Kw = 0, vg = 0.5 m/s, wg = 0".
    for (const char* id : {"fig5_2", "fig5_3", "fig5_4"}) {
        const Study& s = study(id);
        ASSERT_EQ(s.trajectories.size(), 1U) << id;
        const CaseSpec& c = s.trajectories[0];
        EXPECT_EQ(c.kind, CaseKind::line_step) << id;
        EXPECT_EQ(c.line_speed_m_s, 0.5);
        EXPECT_EQ(c.step_m, 0.2);
        EXPECT_EQ(c.step_time_s, 10.0);
        EXPECT_EQ(c.duration_s, 20.0);
        expect_gains(s.fixed, 0.0, 0.0, 0.0, 0.5, 0.0);
    }
    EXPECT_EQ(study("fig5_2").trajectories[0].step_axis, StepAxis::x);
    EXPECT_EQ(study("fig5_3").trajectories[0].step_axis, StepAxis::y);
    EXPECT_EQ(study("fig5_4").trajectories[0].step_axis, StepAxis::y);  // "20cm Step in Y-Axis: Kw Sensitivity"
    EXPECT_EQ(study("fig5_2").varied, SweptGain::kx);
    EXPECT_EQ(study("fig5_3").varied, SweptGain::ky);
    EXPECT_EQ(study("fig5_4").varied, SweptGain::kw);
    EXPECT_EQ(study("fig5_2").values, (std::vector<double>{0, 1, 5, 10}));
    EXPECT_EQ(study("fig5_3").values, (std::vector<double>{0, 1, 5, 10}));
    EXPECT_EQ(study("fig5_4").values, (std::vector<double>{0, 3, 5, 10}));

    // Group 2, group 3 and fig. 5-7: the 1 m, 20 s circle, "vg = 0.3 m/s, wg = 0.3 rad/s".
    for (const char* id : {"a2_circle_kx", "a2_circle_ky", "a2_circle_kw", "fig5_5", "fig5_6", "fig5_7"}) {
        const Study& s = study(id);
        ASSERT_EQ(s.trajectories.size(), 1U) << id;
        const CaseSpec& c = s.trajectories[0];
        EXPECT_EQ(c.kind, CaseKind::circle) << id;
        EXPECT_EQ(c.radius_m, 1.0) << id;
        EXPECT_NEAR(c.rate_rad_s, 2.0 * plant::kPi / 20.0, 1e-15) << id;
        EXPECT_EQ(c.duration_s, 20.0) << id;
        EXPECT_EQ(s.fixed.vref_m_s, 0.3) << id;
        EXPECT_EQ(s.fixed.wref_rad_s, 0.3) << id;
        EXPECT_FALSE(s.goal_feedforward) << id;
        for (double v : s.values) {
            EXPECT_GE(v, 0.0) << id;  // "charted for a gain of 0 through 10"
            EXPECT_LE(v, 10.0) << id;
        }
    }
    EXPECT_EQ(study("a2_circle_kx").varied, SweptGain::kx);
    EXPECT_EQ(study("a2_circle_ky").varied, SweptGain::ky);
    EXPECT_EQ(study("a2_circle_kw").varied, SweptGain::kw);
    expect_gains(study("a2_circle_kx").fixed, 0, 0, 0, 0.3, 0.3);
    // "Kx ranges 0.5 -> 2", first with Ky = 5, Kw = 0, then Ky = 0, Kw = 5.
    EXPECT_EQ(study("fig5_5").varied, SweptGain::kx);
    EXPECT_EQ(study("fig5_5").values, (std::vector<double>{0.5, 1.0, 1.5, 2.0}));
    EXPECT_EQ(study("fig5_5").fixed.ky, 5.0);
    EXPECT_EQ(study("fig5_5").fixed.kw, 0.0);
    EXPECT_EQ(study("fig5_6").values, (std::vector<double>{0.5, 1.0, 1.5, 2.0}));
    EXPECT_EQ(study("fig5_6").fixed.ky, 0.0);
    EXPECT_EQ(study("fig5_6").fixed.kw, 5.0);
    // Fig. 5-7: K_w with K_x = 1, K_y = 6, including the K_w = 8 the thesis picks.
    EXPECT_EQ(study("fig5_7").varied, SweptGain::kw);
    EXPECT_EQ(study("fig5_7").fixed.kx, 1.0);
    EXPECT_EQ(study("fig5_7").fixed.ky, 6.0);
    EXPECT_EQ(study("fig5_7").values.front(), 0.0);
    EXPECT_EQ(study("fig5_7").values.back(), 10.0);
    EXPECT_NE(std::find(study("fig5_7").values.begin(), study("fig5_7").values.end(), 8.0),
              study("fig5_7").values.end());

    // Fig. 5-8: K = (2, 12, 18) on a 0.4 m / 8 s and a 0.6 m / 12 s circle.
    const Study& f8 = study("fig5_8");
    EXPECT_EQ(f8.varied, SweptGain::none);
    ASSERT_EQ(f8.trajectories.size(), 2U);
    EXPECT_EQ(f8.trajectories[0].radius_m, 0.4);
    EXPECT_EQ(f8.trajectories[0].duration_s, 8.0);
    EXPECT_EQ(f8.trajectories[1].radius_m, 0.6);
    EXPECT_EQ(f8.trajectories[1].duration_s, 12.0);
    EXPECT_EQ(f8.fixed.kx, 2.0);
    EXPECT_EQ(f8.fixed.ky, 12.0);
    EXPECT_EQ(f8.fixed.kw, 18.0);
}

TEST(GainSweep, RunsSetTheVariedGainAndFig58TheGoalsVelocity) {
    const std::vector<StudyRun> runs = study_runs(study("fig5_5"));
    ASSERT_EQ(runs.size(), 4U);
    expect_gains(runs[2].gains, 1.5, 5.0, 0.0, 0.3, 0.3);
    EXPECT_EQ(runs[2].value, 1.5);

    const std::vector<StudyRun> f8 = study_runs(study("fig5_8"));
    ASSERT_EQ(f8.size(), 2U);
    // v_g = R w, w_g = w = 2 pi / T: 0.4 x 0.785398 = 0.314159 m/s; 0.6 x 0.523599 = 0.314159 m/s.
    EXPECT_NEAR(f8[0].gains.vref_m_s, 0.4 * 2 * plant::kPi / 8, 1e-15);
    EXPECT_NEAR(f8[0].gains.wref_rad_s, 2 * plant::kPi / 8, 1e-15);
    EXPECT_NEAR(f8[1].gains.wref_rad_s, 2 * plant::kPi / 12, 1e-15);
    EXPECT_EQ(f8[1].gains.kw, 18.0);

    const SimConfig c = run_config(SimConfig{}, f8[1]);
    EXPECT_EQ(c.duration_s, 12.0);
    EXPECT_EQ(c.sample_period_s, kSweepSamplePeriod_s);
    EXPECT_EQ(c.case_spec.radius_m, 0.6);
}

TEST(GainSweep, SelectStudiesKeepsTheListsOrderAndNamesAnUnknownId) {
    EXPECT_EQ(select_studies("all").size(), thesis_studies().size());
    EXPECT_EQ(select_studies("").size(), thesis_studies().size());
    const std::vector<Study> two = select_studies("fig5_8,fig5_2,fig5_8");
    ASSERT_EQ(two.size(), 2U);
    EXPECT_EQ(two[0].id, "fig5_8");
    EXPECT_EQ(two[1].id, "fig5_2");
    try {
        select_studies("fig5_2,fig9_9");
        FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("'fig9_9'"), std::string::npos) << e.what();
    }
    EXPECT_THROW(select_studies("fig5_2,"), std::invalid_argument);  // an empty id
}

// The results belong to their configs whatever the number of workers: the
// same doubles, bit for bit, with 1, 2, 3 (uneven) and 16 (more than runs).
TEST(GainSweep, ParallelRunGivesTheSameBitsWithAnyNumberOfWorkers) {
    std::vector<SimConfig> configs;
    for (const StudyRun& r : study_runs(study("fig5_6"))) {
        SimConfig c = run_config(SimConfig{}, r);  // the motor plant
        c.duration_s = 1.0;
        configs.push_back(c);
    }
    configs.push_back(configs.front());
    configs.back().gains.kw = 0.0;  // five runs, all different
    const std::vector<SimResult> one = simulate_parallel(configs, 1);
    for (unsigned workers : {2u, 3u, 16u}) {
        std::vector<int> done(configs.size(), 0);
        const std::vector<SimResult> many =
            simulate_parallel(configs, workers, [&](std::size_t i) { ++done.at(i); });
        EXPECT_EQ(done, std::vector<int>(configs.size(), 1)) << workers;
        ASSERT_EQ(many.size(), one.size());
        for (std::size_t i = 0; i < one.size(); ++i) {
            ASSERT_EQ(many[i].samples.size(), one[i].samples.size());
            for (std::size_t k = 0; k < one[i].samples.size(); ++k) {
                const SimSample& a = one[i].samples[k];
                const SimSample& b = many[i].samples[k];
                ASSERT_EQ(a.x_m, b.x_m) << workers << " workers, run " << i << ", sample " << k;
                ASSERT_EQ(a.y_m, b.y_m);
                ASSERT_EQ(a.theta_rad, b.theta_rad);
                ASSERT_EQ(a.v_m_s, b.v_m_s);
                ASSERT_EQ(a.ia1_A, b.ia1_A);
            }
        }
    }
    EXPECT_NE(one[0].end_pose.x_m, one[1].end_pose.x_m);  // the runs differ: order matters
}

TEST(GainSweep, ParallelRunValidatesEveryConfigFirst) {
    std::vector<SimConfig> configs(3);
    configs[2].gains.kx = -1.0;
    try {
        simulate_parallel(configs, 2);
        FAIL() << "no throw";
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("run 2: ", 0), 0U) << e.what();
    }
    EXPECT_TRUE(simulate_parallel({}, 4).empty());
}

// Fig. 5-2, K_x = 0, on the kinematic robot. eq. (14) with K_x = K_y = K_w = 0,
// v_g = 0.5, w_g = 0: v = v_g cos(th_e) = 0.5 m/s (th_e = th_g - th = 0 - 0:
// the robot starts on the line heading 0), w = w_g + v_g (0 + 0) = 0. The
// robot drives at exactly the goal's speed and never turns: the error is 0
// before the step and the 20 cm step after it, to the end. Nothing pulls it
// back: with K_x = 0 the longitudinal error does not decay.
TEST(GainSweep, WithKx0TheStepInXNeverDecays) {
    const SimResult r = run_study(study("fig5_2"), kinematic_base())[0];  // K_x = 0
    EXPECT_NEAR(at(r, 9.99).x_m, 0.5 * 9.99, 1e-9);
    EXPECT_NEAR(std::hypot(at(r, 9.99).goal_x_m - at(r, 9.99).x_m, at(r, 9.99).goal_y_m), 0.0, 1e-9);
    for (double t : {10.0, 12.0, 15.0, 20.0}) {
        EXPECT_NEAR(at(r, t).goal_x_m - at(r, t).x_m, 0.2, 1e-9) << t;
        EXPECT_EQ(at(r, t).y_m, 0.0) << t;
        EXPECT_EQ(at(r, t).theta_rad, 0.0) << t;
    }
    const TrackingMetrics m = tracking_metrics(r, study("fig5_2").trajectories[0]);
    EXPECT_NEAR(m.final_error_m, 0.2, 1e-9);
    EXPECT_NEAR(m.max_error_m, 0.2, 1e-9);
    EXPECT_FALSE(m.settling_time_s.has_value());
}

// Fig. 5-2, K_x = 1. After the step, with th = th_e = 0: dx_e/dt = v_g - v =
// v_g - (v_g + K_x x_e) = -K_x x_e, so x_e = 0.2 e^{-K_x (t - 10)}:
// 0.2 / e = 0.073576 m at t = 11 s; inside the 2 cm band from
// t - 10 = ln(10) / K_x = 2.3026 s, i.e. the sample at 12.31 s (12.30 s
// still has 0.02005 m). The control holds each command for a 1e-4 s step:
// (1 - 1e-4)^10000 = e^{-1} (1 - 5e-5), i.e. 0.2 e^{-1} 5e-5 = 3.7e-6 m, inside 1e-5.
TEST(GainSweep, WithKx1TheStepInXDecaysAsExpMinusT) {
    const SimResult r = run_study(study("fig5_2"), kinematic_base())[1];  // K_x = 1
    EXPECT_NEAR(at(r, 11.0).goal_x_m - at(r, 11.0).x_m, 0.2 * std::exp(-1.0), 1e-5);
    EXPECT_NEAR(at(r, 12.0).goal_x_m - at(r, 12.0).x_m, 0.2 * std::exp(-2.0), 1e-5);
    const TrackingMetrics m = tracking_metrics(r, study("fig5_2").trajectories[0]);
    ASSERT_TRUE(m.settling_time_s.has_value());
    EXPECT_NEAR(*m.settling_time_s, 2.31, 1e-9);
    EXPECT_NEAR(m.max_error_m, 0.2, 1e-9);
}

// Fig. 5-4: "K_w has zero effect on either the angular rotation or the
// Y-axis error for the step change at 10 seconds." With K_x = K_y = 0 the
// law is v = v_g cos(th_e), w = v_g K_w sin(th_e), and th_e = 0 - th stays
// 0 on the kinematic robot (it starts heading 0 and w = 0): every K_w gives
// the same run, bit for bit, and the 20 cm sideways error never closes.
TEST(GainSweep, KwHasNoEffectOnTheStepInY) {
    const std::vector<SimResult> runs = run_study(study("fig5_4"), kinematic_base());
    ASSERT_EQ(runs.size(), 4U);
    for (std::size_t i = 1; i < runs.size(); ++i) {
        ASSERT_EQ(runs[i].samples.size(), runs[0].samples.size());
        for (std::size_t k = 0; k < runs[0].samples.size(); ++k) {
            ASSERT_EQ(runs[i].samples[k].x_m, runs[0].samples[k].x_m);
            ASSERT_EQ(runs[i].samples[k].y_m, runs[0].samples[k].y_m);
            ASSERT_EQ(runs[i].samples[k].omega_rad_s, 0.0);
        }
    }
    EXPECT_NEAR(at(runs[3], 20.0).goal_y_m - at(runs[3], 20.0).y_m, 0.2, 1e-12);
    EXPECT_NEAR(tracking_metrics(runs[3], study("fig5_4").trajectories[0]).final_error_m, 0.2, 1e-9);
}

// tracking_metrics by hand on five samples, 1 s apart.
TEST(GainSweep, MetricsByHand) {
    SimResult r;
    const double errors[] = {0.3, 0.01, 0.05, 0.01, 0.0};
    for (int k = 0; k < 5; ++k) {
        SimSample s;
        s.t_s = k;
        s.goal_x_m = 1.0;
        s.x_m = 1.0 - errors[k];
        r.samples.push_back(s);
    }
    CaseSpec circle = circle_case(1.0, 20.0);
    TrackingMetrics m = tracking_metrics(r, circle);
    EXPECT_NEAR(m.final_error_m, 0.0, 1e-15);
    EXPECT_NEAR(m.max_error_m, 0.3, 1e-15);
    // sqrt((0.09 + 0.0001 + 0.0025 + 0.0001 + 0) / 5) = sqrt(0.01854) = 0.136162
    EXPECT_NEAR(m.rms_error_m, std::sqrt(0.01854), 1e-12);
    ASSERT_TRUE(m.settling_time_s.has_value());
    EXPECT_EQ(*m.settling_time_s, 3.0);  // in band from t = 3 s after the 0.05 m at 2 s
    EXPECT_EQ(*tracking_metrics(r, circle, 0.06).settling_time_s, 1.0);

    CaseSpec line = line_step_case(StepAxis::x);  // counted from the step
    line.step_time_s = 2.5;
    EXPECT_EQ(*tracking_metrics(r, line).settling_time_s, 0.5);  // 3 s - 2.5 s

    r.samples.back().x_m = 0.9;  // out of band at the end: not settled
    EXPECT_FALSE(tracking_metrics(r, circle).settling_time_s.has_value());
}

}  // namespace
}  // namespace ddmr::hostsim
