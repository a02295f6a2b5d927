#include "tools/hostsim/host_sim.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "plant/drive_stepper.hpp"
#include "plant/pwm_waveform.hpp"
#include "tools/hostsim/drive_command.hpp"
#include "tools/hostsim/firmware_constants.hpp"
#include "tools/hostsim/firmware_odometry.hpp"
#include "tools/hostsim/kinematic_plant.hpp"

namespace ddmr::hostsim {

namespace {

using Cycles = std::int64_t;
constexpr Cycles kNever = std::numeric_limits<Cycles>::max();

/// The thesis shield's bridge (the dir_pwm truth table): PWM pin low
/// coasts, high drives in the direction pin's direction.
plant::BridgeState bridge_state(bool pwm_high, bool forward) {
    if (!pwm_high) return plant::BridgeState::coast;
    return forward ? plant::BridgeState::forward : plant::BridgeState::reverse;
}

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.9g", v);
    return buf;
}

/// Iterations the sketch runs for `duration_s` (NUM = endtime / dt).
std::int64_t iterations_for(double duration_s) {
    return std::llround(duration_s / firmware::kDt_s);
}

/// Timing of one run, in AVR cycles.
struct Schedule {
    bool loop_period = false;
    Cycles end = 0;             ///< last cycle of the run
    Cycles step = 0;            ///< plant step
    Cycles period = 0;          ///< control period (loop_period)
    std::int64_t iterations = 0;  ///< control iterations (loop_period)
    Cycles sample = 0;          ///< sample interval
    Cycles log = 0;             ///< log interval without loop_period (0.1 s)
    double clock_rate = 1.0;    ///< controller seconds per true second
};

Schedule schedule_of(const SimConfig& c) {
    Schedule s;
    s.loop_period = c.fidelity.has(FidelitySwitch::loop_period);
    s.step = std::max<Cycles>(1, plant::s_to_cycles(c.plant_step_s));
    s.sample = std::max<Cycles>(1, plant::s_to_cycles(c.sample_period_s));
    s.log = plant::s_to_cycles(firmware::kDt_s * firmware::kIterationsPerLog);
    if (s.loop_period) {
        s.period = std::max<Cycles>(1, plant::s_to_cycles(c.period_s));
        s.iterations = iterations_for(c.duration_s);
        s.end = s.period * s.iterations;
        s.clock_rate = firmware::kDt_s / plant::cycles_to_s(s.period);
    } else {
        s.end = plant::s_to_cycles(c.duration_s);
    }
    return s;
}

/// The closed loop, with the controller's arithmetic in Real.
template <class Real>
class Simulation {
  public:
    explicit Simulation(const SimConfig& c)
        : cfg_(c),
          sched_(schedule_of(c)),
          gains_(c.fidelity.has(FidelitySwitch::int_gains) ? integer_gains(c.gains) : c.gains),
          odometry_on_(c.fidelity.has(FidelitySwitch::encoder_odometry)),
          ff_constants_(c.fidelity.has(FidelitySwitch::feedforward_constants)),
          quantised_(c.fidelity.has(FidelitySwitch::pwm_quantisation)),
          eeprom_bytes_(c.fidelity.has(FidelitySwitch::eeprom_bytes)),
          switched_(c.pwm == PwmModel::switched),
          t_ctrl_(Real(0)),
          angref_(static_cast<Real>(c.case_spec.heading0_rad)) {
        if (c.kinematic_plant) {
            kinematic_.emplace(c.plant.kinematics);
        } else {
            robot_.emplace(c.plant);
        }
        result_.effective_gains = gains_;
        result_.eeprom_quantised = eeprom_bytes_;
        result_.eeprom_logged = !eeprom_bytes_ || c.case_spec.logs_eeprom;
        const auto expected_samples = static_cast<std::size_t>(sched_.end / sched_.sample + 2);
        result_.samples.reserve(expected_samples);
    }

    SimResult run() {
        Cycles c = 0;
        bool running = true;
        while (true) {
            if (sched_.loop_period) {
                if (c == next_control_ && iterations_ < sched_.iterations) {
                    estimate_ = estimate_pose();
                    control(c);
                    ++iterations_;
                    next_control_ = iterations_ < sched_.iterations ? iterations_ * sched_.period : kNever;
                    if (iterations_ % firmware::kIterationsPerLog == 0) {
                        log_position(iterations_ * sched_.period);
                    }
                }
            } else {
                const bool log_now = c > 0 && c % sched_.log == 0;
                if (c < sched_.end || log_now) estimate_ = estimate_pose();
                if (c < sched_.end) {
                    control(c);
                    ++iterations_;
                }
                if (log_now) log_position(c);
            }
            if (c % sched_.sample == 0 || c == sched_.end) record_sample(c);
            if (c >= sched_.end || !running) break;
            Cycles next = std::min({sched_.end, c + sched_.step, (c / sched_.sample + 1) * sched_.sample});
            if (sched_.loop_period) {
                next = std::min(next, next_control_);
            } else {
                next = std::min(next, (c / sched_.log + 1) * sched_.log);
            }
            running = advance_plant(c, next);
            c = next;
        }
        finish(c);
        return std::move(result_);
    }

  private:
    // --- the controller's pose --------------------------------------------
    PoseEstimate<Real> estimate_pose() {
        if (odometry_on_) return odometry_.update(robot_->edge_count(0), robot_->edge_count(1));
        const plant::Pose& p = true_pose();
        return {static_cast<Real>(p.x_m), static_cast<Real>(p.y_m), static_cast<Real>(p.theta_rad)};
    }

    // --- one control iteration at cycle c -----------------------------------
    void control(Cycles c) {
        Real t = t_ctrl_;
        Real angref = angref_;
        if (!sched_.loop_period) {
            t = static_cast<Real>(plant::cycles_to_s(c));
            angref = static_cast<Real>(cfg_.case_spec.heading0_rad) +
                     static_cast<Real>(cfg_.case_spec.rate_rad_s) * t;
        }
        const GoalPoint<Real> g = goal_position<Real>(cfg_.case_spec, t);
        const TrackingError<Real> e = tracking_error<Real>(g.x_m, g.y_m, angref, estimate_);
        const VelocityCommand<Real> cmd = kanayama_law<Real>(e, gains_);
        if (kinematic_) {
            const WheelSpeeds<Real> w = inverse_kinematics<Real>(cfg_.plant.kinematics, cmd);
            kinematic_->set_wheel_speeds(static_cast<double>(w.right_rad_s), static_cast<double>(w.left_rad_s));
            for (std::size_t m = 0; m < plant::kMotorCount; ++m) {
                const double speed = kinematic_->wheel_speed_rad_s(m);
                drive_[m].forward = speed > 0.0 ? true : (speed < 0.0 ? false : drive_[m].forward);
            }
        } else {
            drive_motors(cmd);
        }
        if (sched_.loop_period) {
            // `t=t+dt; Angref=Angref+dt*0.5236;`
            const Real dt = static_cast<Real>(firmware::kDt_s);
            t_ctrl_ = t_ctrl_ + dt;
            angref_ = angref_ + dt * static_cast<Real>(cfg_.case_spec.rate_rad_s);
        }
    }

    void drive_motors(const VelocityCommand<Real>& cmd) {
        const WheelSpeeds<Real> phi = ff_constants_ ? firmware_wheel_speeds<Real>(cmd)
                                                    : inverse_kinematics<Real>(cfg_.plant.kinematics, cmd);
        const std::array<Real, plant::kMotorCount> wheel{phi.right_rad_s, phi.left_rad_s};
        const double vb = robot_->battery_voltage_V();
        const double inverse_vb = vb > 0.0 ? 1.0 / vb : 0.0;
        for (std::size_t m = 0; m < plant::kMotorCount; ++m) {
            Real u;
            if (ff_constants_) {
                // `255.0*GR*Ka*(30.3*v+1.92*w)*Batt`
                u = drive_value_255<Real>(static_cast<Real>(firmware::kGearRatio),
                                          static_cast<Real>(firmware::kKa_V_s_per_rad), wheel[m],
                                          static_cast<Real>(firmware::kInverseBattery_per_V));
            } else {
                const plant::DcMotorParams& mp = cfg_.plant.motor[m];
                u = drive_value_255<Real>(static_cast<Real>(mp.gear_ratio),
                                          static_cast<Real>(mp.back_emf_V_s_per_rad), wheel[m],
                                          static_cast<Real>(inverse_vb));
            }
            const double u_d = static_cast<double>(u);
            drive_[m] = quantised_ ? quantised_drive(firmware_int(u_d), pwm_timer_of_motor(m), drive_[m].forward)
                                   : continuous_drive(u_d, drive_[m].forward);
        }
    }

    // --- plant ----------------------------------------------------------------
    const plant::Pose& true_pose() const { return kinematic_ ? kinematic_->pose() : robot_->pose(); }

    /// Steps the plant from cycle `from` to `to` with the drive held.
    bool advance_plant(Cycles from, Cycles to) {
        if (kinematic_) {
            kinematic_->step(plant::cycles_to_s(to - from));
            ++result_.plant_steps;
            return true;
        }
        plant::RobotInput in;
        in.mode = switched_ ? plant::DriveMode::switched : plant::DriveMode::averaged;
        plant::PwmDrive drive;
        for (std::size_t m = 0; m < plant::kMotorCount; ++m) {
            drive.pwm[m].ocr = drive_[m].ocr;  // both counters at BOTTOM at cycle 0
            drive.forward[m] = drive_[m].forward;
            in.bridge[m].duty = drive_[m].duty;
            in.bridge[m].forward = drive_[m].forward;
            in.bridge[m].state = bridge_state(drive_[m].duty > 0.0, drive_[m].forward);
        }
        const plant::DriveStepResult r = plant::step_across_edges(*robot_, in, drive, from, to,
                                                                  static_cast<std::uint32_t>(plant::kCpuHz), edges_);
        result_.plant_steps += r.pieces;
        if (r.status != plant::StepStatus::ok) {
            result_.status = r.status;
            result_.status_at_s = r.t_s;
            return false;
        }
        return true;
    }

    // --- outputs --------------------------------------------------------------
    /// The controller's clock at true cycle c, in double (for the goal columns).
    double controller_time_s(Cycles c) const { return plant::cycles_to_s(c) * sched_.clock_rate; }

    void record_sample(Cycles c) {
        SimSample s;
        s.t_s = plant::cycles_to_s(c);
        const plant::Pose& p = true_pose();
        s.x_m = p.x_m;
        s.y_m = p.y_m;
        s.theta_rad = p.theta_rad;
        if (kinematic_) {
            const plant::BodyVelocity b = kinematic_->body_velocity();
            s.v_m_s = b.v_m_s;
            s.omega_rad_s = b.omega_rad_s;
            s.wheel1_rad_s = kinematic_->wheel_speed_rad_s(0);
            s.wheel2_rad_s = kinematic_->wheel_speed_rad_s(1);
            s.vbatt_V = cfg_.plant.battery.open_circuit_V;
        } else {
            const plant::BodyVelocity b = robot_->body_velocity();
            s.v_m_s = b.v_m_s;
            s.omega_rad_s = b.omega_rad_s;
            s.ia1_A = robot_->motor_current_A(0);
            s.ia2_A = robot_->motor_current_A(1);
            s.wheel1_rad_s = robot_->wheel_speed_rad_s(0);
            s.wheel2_rad_s = robot_->wheel_speed_rad_s(1);
            s.vbatt_V = robot_->battery_voltage_V();
            s.edges1 = robot_->edge_count(0);
            s.edges2 = robot_->edge_count(1);
            s.duty1 = drive_[0].duty;
            s.duty2 = drive_[1].duty;
        }
        s.dir1 = drive_[0].forward;
        s.dir2 = drive_[1].forward;
        const double tc = controller_time_s(c);
        const GoalPoint<double> g = goal_position<double>(cfg_.case_spec, tc);
        s.goal_x_m = g.x_m;
        s.goal_y_m = g.y_m;
        const PoseEstimate<double> truth{p.x_m, p.y_m, p.theta_rad};
        s.lyapunov = lyapunov(tracking_error<double>(g.x_m, g.y_m, goal_heading_rad(cfg_.case_spec, tc), truth),
                              gains_.ky);
        result_.samples.push_back(s);
    }

    /// Logs the controller's current pose estimate, written at cycle c.
    void log_position(Cycles c) {
        if (!result_.eeprom_logged) return;
        EepromLogEntry e;
        e.sample = static_cast<int>(result_.eeprom_log.size());
        e.t_s = plant::cycles_to_s(c);
        if (eeprom_bytes_) {
            if (e.sample >= firmware::kLogMaxSamples) {
                result_.eeprom_truncated = true;
                return;
            }
            // `EEPROM.write(addr,int(Ex*250.0));`: int() in the 16-bit range, low byte.
            const Real scale = static_cast<Real>(firmware::kLogCountsPerMetre);
            e.x_counts = firmware_int(static_cast<double>(estimate_.x_m * scale));
            e.y_counts = firmware_int(static_cast<double>(estimate_.y_m * scale));
            e.x_byte = static_cast<std::uint8_t>(e.x_counts & 0xFF);
            e.y_byte = static_cast<std::uint8_t>(e.y_counts & 0xFF);
            e.x_m = e.x_counts / firmware::kLogCountsPerMetre;
            e.y_m = e.y_counts / firmware::kLogCountsPerMetre;
        } else {
            e.x_m = static_cast<double>(estimate_.x_m);
            e.y_m = static_cast<double>(estimate_.y_m);
        }
        result_.eeprom_log.push_back(e);
    }

    void finish(Cycles c) {
        result_.end_pose = true_pose();
        result_.end_time_s = plant::cycles_to_s(c);
        result_.end_estimate = {static_cast<double>(estimate_.x_m), static_cast<double>(estimate_.y_m),
                                static_cast<double>(estimate_.theta_rad)};
        result_.controller_end_time_s =
            sched_.loop_period ? static_cast<double>(t_ctrl_) : plant::cycles_to_s(c);
        const GoalPoint<double> g = goal_position<double>(cfg_.case_spec, result_.controller_end_time_s);
        result_.goal_end_x_m = g.x_m;
        result_.goal_end_y_m = g.y_m;
        result_.control_iterations = static_cast<std::uint64_t>(iterations_);
    }

    const SimConfig& cfg_;
    Schedule sched_;
    Gains gains_;
    bool odometry_on_;
    bool ff_constants_;
    bool quantised_;
    bool eeprom_bytes_;
    bool switched_;

    std::optional<plant::Robot> robot_;
    std::optional<KinematicPlant> kinematic_;
    plant::EdgeBuffer edges_;

    FirmwareOdometry<Real> odometry_;
    PoseEstimate<Real> estimate_{};
    Real t_ctrl_;   ///< the sketch's `t` (loop_period)
    Real angref_;   ///< the sketch's `Angref` (loop_period)
    std::array<BridgeCommand, plant::kMotorCount> drive_{};
    std::int64_t iterations_ = 0;
    Cycles next_control_ = 0;

    SimResult result_;
};

}  // namespace

const char* to_string(Model m) { return m == Model::ideal ? "ideal" : "firmware"; }

Model parse_model(const std::string& s) {
    if (s == "ideal") return Model::ideal;
    if (s == "firmware") return Model::firmware;
    throw std::invalid_argument("model '" + s + "': must be ideal or firmware");
}

const char* to_string(PwmModel m) { return m == PwmModel::averaged ? "averaged" : "switched"; }

Gains default_gains(const CaseSpec& c) {
    Gains g;
    g.kx = firmware::kKxAsWritten;
    g.ky = firmware::kKy;
    g.kw = firmware::kKw;
    if (c.name == "case1" || c.name == "case2") {
        g.vref_m_s = firmware::kVref_m_s;
        g.wref_rad_s = firmware::kWref_rad_s;
    } else {
        const GoalVelocity v = goal_velocity(c);
        g.vref_m_s = v.v_m_s;
        g.wref_rad_s = v.omega_rad_s;
    }
    return g;
}

SimConfig config_for_case(int case_number, Model model) {
    SimConfig c;
    c.model = model;
    c.fidelity = model == Model::firmware ? Fidelity::all() : Fidelity::none();
    c.case_spec = firmware_case(case_number);
    c.gains = default_gains(c.case_spec);
    c.plant = plant::default_robot_params();
    c.duration_s = c.case_spec.duration_s;
    c.period_s = firmware::kDt_s;
    c.plant_step_s = c.plant.stepper.max_step_s;
    return c;
}

void validate(const SimConfig& c) {
    require(c.model == Model::ideal || c.fidelity.is_all(),
            "model firmware has every fidelity switch on (got " + c.fidelity.to_string() +
                "); use model ideal with the switches wanted");
    validate(c.case_spec);
    validate(c.gains);
    plant::validate(c.plant);
    require(c.duration_s > 0.0 && c.duration_s <= 3600.0,
            "duration " + num(c.duration_s) + " s: must be in (0, 3600]");
    require(c.period_s >= 1e-4 && c.period_s <= 1.0, "period " + num(c.period_s) + " s: must be in [1e-4, 1]");
    require(c.plant_step_s >= plant::cycles_to_s(1) && c.plant_step_s <= 0.01,
            "plant step " + num(c.plant_step_s) + " s: must be in [62.5e-9, 0.01]");
    require(c.sample_period_s >= 1e-5 && c.sample_period_s <= 1.0,
            "sample period " + num(c.sample_period_s) + " s: must be in [1e-5, 1]");
    if (c.fidelity.has(FidelitySwitch::loop_period)) {
        const double n = static_cast<double>(iterations_for(c.duration_s));
        require(n >= 1.0 && std::abs(n * firmware::kDt_s - c.duration_s) < 1e-9,
                "duration " + num(c.duration_s) +
                    " s: with loop_period the firmware runs whole iterations of dt = 0.01 s");
    }
    if (c.kinematic_plant) {
        require(c.model == Model::ideal, "the kinematic plant runs the ideal model only");
        for (FidelitySwitch s : {FidelitySwitch::encoder_odometry, FidelitySwitch::feedforward_constants,
                                 FidelitySwitch::pwm_quantisation}) {
            require(!c.fidelity.has(s), std::string("fidelity switch ") + to_string(s) +
                                            " needs the dynamic plant (motors, encoders), not the kinematic one");
        }
        require(c.pwm == PwmModel::averaged, "the kinematic plant has no PWM: use pwm averaged");
    }
}

SimResult simulate(const SimConfig& config) {
    validate(config);
    if (config.fidelity.has(FidelitySwitch::float32)) return Simulation<float>(config).run();
    return Simulation<double>(config).run();
}

}  // namespace ddmr::hostsim
