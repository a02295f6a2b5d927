#include "tools/hostsim/host_sim.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

namespace ddmr::hostsim {
namespace {

double end_distance(const SimResult& a, const SimResult& b) {
    return std::hypot(a.end_pose.x_m - b.end_pose.x_m, a.end_pose.y_m - b.end_pose.y_m);
}

double goal_distance(const SimResult& r) {
    return std::hypot(r.goal_end_x_m - r.end_pose.x_m, r.goal_end_y_m - r.end_pose.y_m);
}

SimConfig short_case1(Model m, double seconds) {
    SimConfig c = config_for_case(1, m);
    c.duration_s = seconds;
    return c;
}

TEST(HostSim, ConfigForCaseHasTheFirmwaresDefaults) {
    const SimConfig c = config_for_case(1, Model::firmware);
    EXPECT_TRUE(c.fidelity.is_all());
    EXPECT_EQ(c.gains.kx, 1.1);  // as written; int_gains makes it 1
    EXPECT_EQ(c.gains.vref_m_s, 0.2);
    EXPECT_EQ(c.gains.wref_rad_s, 0.2);
    EXPECT_EQ(c.duration_s, 12.0);
    EXPECT_EQ(c.period_s, 0.01);
    EXPECT_EQ(c.plant_step_s, 1e-4);  // the plant's max_step_s (default.yaml)
    EXPECT_TRUE(config_for_case(2, Model::ideal).fidelity.is_none());
    EXPECT_EQ(config_for_case(2, Model::ideal).duration_s, 8.0);
}

// The first control iteration of the firmware model drives the bridges with
// the sketch's Vdc1 = 234, Vdc2 = 159 (drive_command_test.cpp by hand).
TEST(HostSim, FirmwareModelFirstIterationDrives234And159) {
    const SimResult r = simulate(short_case1(Model::firmware, 0.02));
    ASSERT_FALSE(r.samples.empty());
    EXPECT_DOUBLE_EQ(r.samples[0].duty1, 234.0 / 255.0);
    EXPECT_DOUBLE_EQ(r.samples[0].duty2, 159.0 / 255.0);
    EXPECT_TRUE(r.samples[0].dir1);
    EXPECT_TRUE(r.samples[0].dir2);
    EXPECT_EQ(r.control_iterations, 2U);
}

TEST(HostSim, FirmwareModelWrites120EepromSamplesInCase1AndNoneInCase2) {
    const SimResult r = simulate(config_for_case(1, Model::firmware));
    EXPECT_EQ(r.status, plant::StepStatus::ok);
    EXPECT_EQ(r.control_iterations, 1200U);
    ASSERT_TRUE(r.eeprom_logged);
    ASSERT_EQ(r.eeprom_log.size(), 120U);
    for (const EepromLogEntry& e : r.eeprom_log) {
        EXPECT_NEAR(e.t_s, (e.sample + 1) * 0.1, 1e-12);  // after each 10th 10 ms iteration
        EXPECT_EQ(e.x_byte, static_cast<std::uint8_t>(e.x_counts & 0xFF));
        EXPECT_DOUBLE_EQ(e.x_m, e.x_counts / 250.0);  // 4 mm steps
        EXPECT_DOUBLE_EQ(e.y_m, e.y_counts / 250.0);
    }
    // The last sample is the controller's last pose, truncated toward zero to 4 mm.
    EXPECT_EQ(r.eeprom_log.back().x_counts, static_cast<int>(static_cast<float>(r.end_estimate.x_m) * 250.0F));
    EXPECT_EQ(r.samples.size(), 12001U);  // 1 kHz, both ends

    const SimResult r2 = simulate(config_for_case(2, Model::firmware));
    EXPECT_FALSE(r2.eeprom_logged);
    EXPECT_TRUE(r2.eeprom_log.empty());
    EXPECT_EQ(r2.control_iterations, 800U);
}

TEST(HostSim, IdealLogsTheTruePoseEveryTenthOfASecondUnquantised) {
    const SimResult r = simulate(config_for_case(2, Model::ideal));
    ASSERT_TRUE(r.eeprom_logged);  // every case in the ideal model
    ASSERT_EQ(r.eeprom_log.size(), 80U);
    for (const EepromLogEntry& e : r.eeprom_log) {
        const SimSample& s = r.samples[static_cast<std::size_t>((e.sample + 1) * 100)];
        EXPECT_NEAR(s.t_s, e.t_s, 1e-12);
        EXPECT_EQ(e.x_m, s.x_m);
        EXPECT_EQ(e.y_m, s.y_m);
    }
}

// eq. (16): with the kinematic plant (the robot moves at the commanded v, w
// at once) and the goal's true velocities as feed-forward (v_g = R w > 0),
// eq. (15) never increases. The only departure allowed is the zero-order hold
// of the command over a 1e-4 s step (O(h^2) per step).
TEST(HostSim, LyapunovNonIncreasingWithTheKinematicPlant) {
    for (const CaseSpec& cs : {circle_case(0.6, 12.0), circle_case(0.4, 8.0)}) {
        SimConfig c = config_for_case(1, Model::ideal);
        c.case_spec = cs;
        c.gains = default_gains(cs);
        c.duration_s = cs.duration_s;
        c.kinematic_plant = true;
        const SimResult r = simulate(c);
        ASSERT_GT(r.samples.size(), 1000U);
        const double v0 = r.samples.front().lyapunov;
        EXPECT_NEAR(v0, 0.5 * cs.radius_m * cs.radius_m + (1.0 - std::cos(cs.heading0_rad)) / 6.0, 1e-12);
        double worst_rise = -1.0;
        for (std::size_t k = 1; k < r.samples.size(); ++k) {
            worst_rise = std::max(worst_rise, r.samples[k].lyapunov - r.samples[k - 1].lyapunov);
        }
        EXPECT_LE(worst_rise, 1e-12) << cs.name << " R = " << cs.radius_m;
        EXPECT_LT(r.samples.back().lyapunov, 1e-5 * v0);  // converging within one lap
        EXPECT_LT(goal_distance(r), 3e-3);
    }
}

// With the sketch's feed-forward (vref = wref = 0.2, not the goal's 0.314 m/s
// and 0.5236 rad/s) the kinematic loop settles to a constant error pose, the
// equilibrium of eqs. (13) and (14) with w_R = w = 0.5236, v_G = 0.6 w:
//   y_e' = 0: x_e = v_G sin th_e / w
//   w law   : 6 y_e + 8 sin th_e = (w - 0.2) / 0.2
//   x_e' = 0: y_e w + v_G cos th_e = 0.2 cos th_e + 1.1 x_e
// Bisection: th_e = 0.18764, x_e = 0.11193 m, y_e = 0.02094 m, so after one
// lap, with the goal at (0.6, 0) heading 1.571 + 2 pi, the robot is at
// (0.59972, -0.11386) m. (The thesis's MATLAB run ended at (0.585, -0.112).)
TEST(HostSim, KinematicCase1EndsAtTheEquilibriumOfEqs13And14) {
    const double w = 0.5236, vg = 0.6 * w, kx = 1.1, ky = 6.0, kw = 8.0, vr = 0.2, wr = 0.2;
    auto residual = [&](double th) {
        const double xe = vg * std::sin(th) / w;
        const double ye = ((w - wr) / vr - kw * std::sin(th)) / ky;
        return ye * w + vg * std::cos(th) - (vr * std::cos(th) + kx * xe);
    };
    double lo = 0.0, hi = 1.5;
    ASSERT_LT(residual(lo) * residual(hi), 0.0);
    for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        (residual(lo) * residual(mid) <= 0.0 ? hi : lo) = mid;
    }
    const double th = lo, xe = vg * std::sin(th) / w, ye = ((w - wr) / vr - kw * std::sin(th)) / ky;
    EXPECT_NEAR(th, 0.18764, 1e-5);
    const double theta_robot = 1.571 + w * 12.0 - th;
    const double x = 0.6 * std::cos(w * 12.0) - (std::cos(theta_robot) * xe - std::sin(theta_robot) * ye);
    const double y = 0.6 * std::sin(w * 12.0) - (std::sin(theta_robot) * xe + std::cos(theta_robot) * ye);
    EXPECT_NEAR(x, 0.59972, 1e-5);
    EXPECT_NEAR(y, -0.11386, 1e-5);

    SimConfig c = config_for_case(1, Model::ideal);
    c.kinematic_plant = true;
    const SimResult r = simulate(c);
    EXPECT_NEAR(r.end_pose.x_m, x, 2e-3);
    EXPECT_NEAR(r.end_pose.y_m, y, 2e-3);
}

// The ideal model with motor dynamics tracks, but lags: its eq. (17)
// feed-forward knows neither the L298's drop nor R_a I (docs/hostsim.md).
TEST(HostSim, IdealCase1WithMotorsTracksTheCircle) {
    const SimResult r = simulate(config_for_case(1, Model::ideal));
    EXPECT_EQ(r.status, plant::StepStatus::ok);
    EXPECT_EQ(r.samples.size(), 12001U);
    EXPECT_NEAR(r.end_time_s, 12.0, 1e-12);
    EXPECT_GT(r.end_pose.theta_rad, 2.0 * 3.14159);  // went round once
    EXPECT_LT(goal_distance(r), 0.3);
    std::printf("ideal case 1 end (%.4f, %.4f), %.4f m from the goal\n", r.end_pose.x_m, r.end_pose.y_m,
                goal_distance(r));
}

TEST(HostSim, IntGainsAloneChangesTheRun) {
    SimConfig ideal = short_case1(Model::ideal, 3.0);
    SimConfig ints = ideal;
    ints.fidelity = Fidelity::parse("int_gains");
    const SimResult a = simulate(ideal);
    const SimResult b = simulate(ints);
    EXPECT_EQ(b.effective_gains.kx, 1.0);
    EXPECT_EQ(a.effective_gains.kx, 1.1);
    EXPECT_GT(end_distance(a, b), 1e-3);
}

// Each switch on alone changes the run (eeprom_bytes only the log). float32
// alone moves the end by nanometres only: on the true pose, every plant step,
// the feedback absorbs float rounding (docs/hostsim.md).
TEST(HostSim, EverySwitchAloneIsReal) {
    const SimConfig ideal = short_case1(Model::ideal, 2.0);
    const SimResult base = simulate(ideal);
    for (const char* name : fidelity_switch_names()) {
        SimConfig c = ideal;
        c.fidelity = Fidelity::parse(name);
        const SimResult r = simulate(c);
        EXPECT_EQ(r.status, plant::StepStatus::ok) << name;
        if (std::string(name) == "eeprom_bytes") {
            EXPECT_EQ(end_distance(base, r), 0.0);
            ASSERT_EQ(r.eeprom_log.size(), 20U);
            bool any_difference = false;
            for (std::size_t k = 0; k < r.eeprom_log.size(); ++k) {
                any_difference |= r.eeprom_log[k].x_m != base.eeprom_log[k].x_m;
            }
            EXPECT_TRUE(any_difference);
        } else {
            EXPECT_GT(end_distance(base, r), 0.0) << name;
        }
    }
}

TEST(HostSim, FirmwareModelIsIdealWithEverySwitch) {
    SimConfig ideal_all = short_case1(Model::ideal, 1.0);
    ideal_all.fidelity = Fidelity::all();
    const SimResult a = simulate(ideal_all);
    const SimResult b = simulate(short_case1(Model::firmware, 1.0));
    EXPECT_EQ(a.end_pose.x_m, b.end_pose.x_m);
    EXPECT_EQ(a.end_pose.y_m, b.end_pose.y_m);
    EXPECT_EQ(a.eeprom_log.size(), b.eeprom_log.size());
}

TEST(HostSim, LoopPeriodRunsTheSketchsIterationsAtTheGivenPeriod) {
    SimConfig c = config_for_case(1, Model::firmware);
    c.period_s = 0.01044;
    const SimResult r = simulate(c);
    EXPECT_EQ(r.control_iterations, 1200U);
    EXPECT_NEAR(r.end_time_s, 1200 * 0.01044, 1e-9);    // 12.528 s of true time
    EXPECT_NEAR(r.controller_end_time_s, 12.0, 1e-3);   // the sketch's t, summed in float
    EXPECT_NE(r.controller_end_time_s, 12.0);
    ASSERT_EQ(r.eeprom_log.size(), 120U);
    EXPECT_NEAR(r.eeprom_log.back().t_s, 12.528, 1e-9);
    // The goal columns follow the firmware's slow clock: at 12.528 s true time, 12.0 s of goal.
    EXPECT_NEAR(r.samples.back().goal_x_m, 0.6 * std::cos(0.5236 * 12.0), 1e-9);
}

TEST(HostSim, SwitchedPwmRuns) {
    SimConfig c = short_case1(Model::firmware, 1.0);
    c.pwm = PwmModel::switched;
    const SimResult r = simulate(c);
    EXPECT_EQ(r.status, plant::StepStatus::ok);
    // 1 s at 1e-4 s is 10,000 steps; splitting at every PWM edge (2 per
    // 2.04 ms period per motor, where they do not coincide) adds up to ~1,960.
    EXPECT_GT(r.plant_steps, 11000U);
    EXPECT_LT(r.plant_steps, 12000U);
    EXPECT_GT(r.end_pose.x_m, 0.05);
}

TEST(HostSim, Deterministic) {
    const SimConfig c = short_case1(Model::firmware, 2.0);
    const SimResult a = simulate(c);
    const SimResult b = simulate(c);
    ASSERT_EQ(a.samples.size(), b.samples.size());
    for (std::size_t k = 0; k < a.samples.size(); ++k) {
        const SimSample& s = a.samples[k];
        const SimSample& t = b.samples[k];
        ASSERT_TRUE(s.x_m == t.x_m && s.y_m == t.y_m && s.theta_rad == t.theta_rad && s.ia1_A == t.ia1_A &&
                    s.edges1 == t.edges1 && s.duty2 == t.duty2)
            << "sample " << k;
    }
    ASSERT_EQ(a.eeprom_log.size(), b.eeprom_log.size());
    for (std::size_t k = 0; k < a.eeprom_log.size(); ++k) EXPECT_EQ(a.eeprom_log[k].x_byte, b.eeprom_log[k].x_byte);
}

TEST(HostSim, ValidateRejectsBadConfigurationsNamingThem) {
    auto message = [](const SimConfig& c) {
        try {
            validate(c);
        } catch (const std::invalid_argument& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    SimConfig subset = config_for_case(1, Model::firmware);
    subset.fidelity = Fidelity::parse("float32");
    EXPECT_NE(message(subset).find("firmware"), std::string::npos);

    SimConfig kin = config_for_case(1, Model::ideal);
    kin.kinematic_plant = true;
    kin.fidelity = Fidelity::parse("encoder_odometry");
    EXPECT_NE(message(kin).find("encoder_odometry"), std::string::npos);

    SimConfig odd = config_for_case(1, Model::firmware);
    odd.duration_s = 0.005;
    EXPECT_NE(message(odd).find("duration"), std::string::npos);

    SimConfig step = config_for_case(1, Model::ideal);
    step.plant_step_s = 0.5;
    EXPECT_NE(message(step).find("plant step"), std::string::npos);

    SimConfig gains = config_for_case(1, Model::ideal);
    gains.gains.kw = -1.0;
    EXPECT_NE(message(gains).find("kw"), std::string::npos);
    EXPECT_THROW(simulate(gains), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::hostsim
