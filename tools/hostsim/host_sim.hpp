#pragma once
// The host reference simulation: the thesis's closed-loop simulator (ch. 5,
// appendix A1) on the same plant as the HIL (plant::Robot), with the
// firmware's differences from it as switches (fidelity.hpp).
//
//   goal (goal_trajectory.hpp) -> eq. (12) error -> eq. (14) law (kanayama.hpp)
//     -> inverse eq. (6), eq. (17), PWM (drive_command.hpp) -> plant::Robot
//     -> true pose, or edge counts -> dead reckoning (firmware_odometry.hpp)
//
// Model::ideal, no switch on (the thesis's idealisation):
//   every plant step (plant_step_s, default the plant's 1e-4 s) the control
//   law runs in double on the TRUE pose at the step's start, with the goal at
//   the true time t and theta_g = theta_0 + w t, gains as given; wheel speeds
//   by the inverse of eq. (6) with the plant's r_1, r_2, L; V = GR K_a phi with
//   the plant motor's GR and K_a; duty = min(|V| / V_batt, 1) with the
//   battery's voltage now; the L298 in DriveMode::averaged. The command is
//   held over the step (zero-order hold). Nothing is quantised.
// Model::firmware = ideal with every switch on; Model::ideal with some
// switches = ideal plus those. Per switch:
//   int_gains         K_x, K_y, K_w truncated (integer_gains): kx 1.1 -> 1.
//   float32           the goal, the controller's clock, eqs. (12), (14), the
//                     feed-forward and the odometry evaluated in float with the
//                     sketch's order of operations. The plant stays double.
//                     (Host cosf/sinf may differ from avr-libc's by an ulp.)
//   encoder_odometry  the controller's pose is FirmwareOdometry on the plant's
//                     edge counts (no direction), read at each control instant.
//   loop_period       the control runs at t = k period_s (k = 0 .. N-1, N =
//                     duration_s / 0.01), with zero compute delay: the new
//                     drive applies from t = k period_s until the next
//                     iteration. The controller's clock advances by the
//                     sketch's dt = 0.01 s per iteration (`t=t+dt;
//                     Angref=Angref+dt*w;`), so with period_s = 10.44 ms the goal
//                     runs 4.4 % slow against real time and the run lasts
//                     N x 10.44 ms. The OCR's double buffering (a new duty
//                     starts at the next PWM TOP, up to 2 ms later), the 1.1 ms
//                     compute time and the analogWrite(50/30) before the first
//                     iteration are not modelled. Off: the control runs every
//                     plant step and the run lasts duration_s.
//   feedforward_constants  phi = 30.3 v +- 1.92 w, V = 48 x 0.0054 phi,
//                     u = 255 V x 0.164 (battery taken as 1 / 0.164 V).
//   pwm_quantisation  Vdc = int(u), the sketch's clamping and direction
//                     logic and analogWrite's handling of negative values
//                     (drive_command.hpp); duty = OCR / 255.
//   eeprom_bytes      the position log holds what the sketch writes: int(E x
//                     250) truncated, its low byte (decoded by unwrapping:
//                     counts / 250 m), only when the case logs (case 1 and the
//                     custom cases; not case 2), at most 250 samples. Off: the
//                     controller's pose, unquantised, for every case.
// The position log (EEPROM log) holds the CONTROLLER's pose (the true pose
// unless encoder_odometry): with loop_period after every 10th iteration, the
// pose of that iteration, stamped at the end of its period (10 k x period_s;
// the sketch writes after the 10th delay(9)); without loop_period every
// 0.1 s of true time.
//
// The goal columns and the Lyapunov function of the samples use the goal in
// double at the controller's clock (true time x 0.01 / period_s with
// loop_period, true time without) and the TRUE pose, with the effective K_y.
//
// Deterministic: no wall clock, no global state, no randomness (the plant's
// encoder jitter is off by default and seeded when on). Time is counted in
// AVR cycles (16 MHz): every step length, period and sample instant is a
// whole number of cycles (62.5 ns), rounded from the seconds given.

#include <cstdint>
#include <string>
#include <vector>

#include "plant/robot.hpp"
#include "plant/robot_params.hpp"
#include "tools/hostsim/fidelity.hpp"
#include "tools/hostsim/goal_trajectory.hpp"
#include "tools/hostsim/kanayama.hpp"

namespace ddmr::hostsim {

enum class Model { ideal, firmware };
const char* to_string(Model m);
/// "ideal" or "firmware"; throws std::invalid_argument naming the value.
Model parse_model(const std::string& s);

enum class PwmModel {
    averaged,  ///< the L298 sees the duty (the thesis's assumption, the default)
    switched,  ///< the Uno's 490 Hz phase-correct waveform, steps split at its edges
};
const char* to_string(PwmModel m);

struct SimConfig {
    /// A label: ideal runs `fidelity` as given; firmware requires Fidelity::all().
    Model model = Model::ideal;
    Fidelity fidelity = Fidelity::none();
    CaseSpec case_spec = firmware_case(1);
    /// As given; int_gains truncates K_x, K_y, K_w.
    Gains gains{};
    plant::RobotParams plant = plant::default_robot_params();
    /// KinematicPlant instead of plant::Robot (ideal model only; switches
    /// int_gains, float32, loop_period only; averaged PWM).
    bool kinematic_plant = false;
    PwmModel pwm = PwmModel::averaged;
    /// Run length on the controller's clock [s], (0, 3600]: the sketch's
    /// NUM x dt. With loop_period it must be a whole number of 0.01 s.
    double duration_s = 12.0;
    /// Control period with loop_period [s], [1e-4, 1]; the HIL measures ~0.01044.
    double period_s = 0.01;
    /// Plant step [s], [62.5e-9, 0.01]; the plant subdivides it to its own
    /// max_step_s. Without loop_period the control also runs at this rate.
    double plant_step_s = 1e-4;
    /// Interval of SimResult::samples [s], [1e-5, 1]: 1 kHz like truth.csv.
    double sample_period_s = 1e-3;
};

/// The firmware's defaults for case 1 or 2: its circle and duration, its
/// gains as written (1.1, 6, 8, vref = wref = 0.2), period 0.01 s, the
/// default plant, averaged PWM; fidelity none (ideal) or all (firmware).
SimConfig config_for_case(int case_number, Model model);

/// Default gains for a case: K = (1.1, 6, 8); v_g, w_g = the sketch's 0.2,
/// 0.2 for cases 1 and 2, the goal's own velocity (goal_velocity) otherwise.
Gains default_gains(const CaseSpec& c);

/// Throws std::invalid_argument naming the field and the value.
void validate(const SimConfig& config);

/// One row of sim.csv: the plant's truth (the columns of truth.csv), the
/// drive of the interval that starts at t_s, the goal and eq. (15).
struct SimSample {
    double t_s = 0.0;                         ///< true time since the case started [s]
    double x_m = 0.0, y_m = 0.0;              ///< true position of P [m]
    double theta_rad = 0.0;                   ///< true heading, not wrapped [rad]
    double v_m_s = 0.0, omega_rad_s = 0.0;    ///< true body velocity
    double ia1_A = 0.0, ia2_A = 0.0;          ///< armature currents (0: kinematic plant)
    double wheel1_rad_s = 0.0, wheel2_rad_s = 0.0;  ///< wheel speeds, motor 1 = right
    double vbatt_V = 0.0;                     ///< battery terminal voltage
    std::uint64_t edges1 = 0, edges2 = 0;     ///< encoder edges so far (0: kinematic plant)
    double duty1 = 0.0, duty2 = 0.0;          ///< bridge duty [0, 1]
    bool dir1 = true, dir2 = true;            ///< direction pins (true = forward)
    double goal_x_m = 0.0, goal_y_m = 0.0;    ///< goal position (double, controller's clock)
    double lyapunov = 0.0;                    ///< eq. (15), true pose vs goal; NaN if K_y = 0
};

/// One sample of the position log (the sketch's EEPROM log).
struct EepromLogEntry {
    int sample = 0;        ///< k, from 0
    double t_s = 0.0;      ///< true time of the write since the case started [s]
    double x_m = 0.0;      ///< logged x [m]: counts / 250 (eeprom_bytes) or the pose
    double y_m = 0.0;
    int x_counts = 0;      ///< eeprom_bytes: int(Ex * 250) before the byte wrap; else 0
    int y_counts = 0;
    std::uint8_t x_byte = 0;  ///< eeprom_bytes: the byte at address 2k; else 0
    std::uint8_t y_byte = 0;  ///< the byte at 2k + 500
};

struct SimResult {
    std::vector<SimSample> samples;        ///< every sample_period_s from 0, and the end
    bool eeprom_logged = false;            ///< false: this case/switch set writes no log
    bool eeprom_quantised = false;         ///< eeprom_bytes was on
    bool eeprom_truncated = false;         ///< more than 250 byte samples were due; the rest dropped
    std::vector<EepromLogEntry> eeprom_log;
    plant::Pose end_pose{};                ///< true pose at the end
    PoseEstimate<double> end_estimate{};   ///< the controller's last pose
    double end_time_s = 0.0;               ///< true time at the end [s]
    double controller_end_time_s = 0.0;    ///< the controller's clock at the end (the sketch's t)
    double goal_end_x_m = 0.0;             ///< goal at controller_end_time_s (the sketch's Gx)
    double goal_end_y_m = 0.0;
    std::uint64_t control_iterations = 0;
    std::uint64_t plant_steps = 0;
    plant::StepStatus status = plant::StepStatus::ok;  ///< not ok: the plant stopped early
    double status_at_s = 0.0;              ///< when it stopped
    Gains effective_gains{};               ///< after int_gains
};

/// Runs the closed loop. Throws std::invalid_argument for a bad config
/// (validate); never throws once running: a plant failure ends the run with
/// status set.
SimResult simulate(const SimConfig& config);

}  // namespace ddmr::hostsim
