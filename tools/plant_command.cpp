// `ddmr-hil plant --duty D1,D2 [--dir F|R,F|R] [--pwm averaged|switched]
//                 [--seconds S] [--plant FILE] [--out DIR]`
//
// Open-loop run of ddmr::plant::Robot with constant inputs. In switched mode
// the enable pins carry the Uno's real 490.2 Hz phase-correct waveform for
// OCR = round(D x 255) (plant/pwm_waveform.hpp); in averaged mode the bridges
// get the duty D itself. Time advances in whole AVR cycles; the plant is
// stepped to every PWM edge and every 1 ms sample (it subdivides internally).
// Every option and the parameter file are checked before the output folder
// is touched.
#include "plant_command.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/truth_csv.hpp"
#include "exit_codes.hpp"
#include "plant/drive_stepper.hpp"
#include "plant/params_yaml.hpp"
#include "plant/pwm_waveform.hpp"
#include "plant/robot.hpp"
#include "plant/units.hpp"

namespace ddmr::tools {

namespace {

namespace pl = ddmr::plant;

struct PlantOptions {
    std::vector<double> duty;
    std::vector<std::string> dir{"F", "F"};
    std::string pwm = "averaged";
    double seconds = 3.0;
    std::string plant_file;
    std::string out = "out/plant";
};

constexpr std::int64_t kSampleCycles = pl::kCpuHz / 1000;  // 1 kHz rows

void append_row(std::string& csv, const pl::Robot& r, std::int64_t cycle) {
    append_truth_row(csv, hil::truth_sample_of(r, static_cast<hil::Cycles>(cycle)), /*with_drive=*/false);
}

int run_plant(const PlantOptions& o) {
    // --- validate everything first -----------------------------------------
    if (o.duty.size() != 2) throw std::invalid_argument("--duty needs two values: D1,D2");
    for (double d : o.duty) {
        if (!(d >= 0.0 && d <= 1.0)) {
            throw std::invalid_argument(fmt::format("--duty {}: each duty must be in [0, 1]", d));
        }
    }
    if (o.dir.size() != 2) throw std::invalid_argument("--dir needs two values: F|R,F|R");
    if (!(o.seconds > 0.0 && o.seconds <= 3600.0)) {
        throw std::invalid_argument(fmt::format("--seconds {}: must be in (0, 3600]", o.seconds));
    }
    const pl::RobotParams params =
        o.plant_file.empty() ? pl::default_robot_params() : pl::load_robot_params(o.plant_file);
    const bool switched = o.pwm == "switched";
    const std::filesystem::path out_dir(o.out);
    prepare_output_dir(out_dir);

    // --- run -----------------------------------------------------------------
    pl::Robot robot(params);
    pl::PwmDrive drive;
    pl::RobotInput in;
    in.mode = switched ? pl::DriveMode::switched : pl::DriveMode::averaged;
    for (std::size_t m = 0; m < pl::kMotorCount; ++m) {
        drive.pwm[m].ocr = pl::PhaseCorrectPwm::ocr_for_duty(o.duty[m]);
        drive.forward[m] = o.dir[m] == "F";
        in.bridge[m].duty = o.duty[m];
        in.bridge[m].forward = drive.forward[m];
    }
    const std::int64_t end = pl::s_to_cycles(o.seconds);
    const std::int64_t half = end / 2;  // mean speeds over the second half
    std::array<double, pl::kMotorCount> angle_at_half{};
    std::string csv = truth_csv_header(/*with_drive=*/false);
    append_row(csv, robot, 0);
    pl::EdgeBuffer edges;
    pl::StepStatus status = pl::StepStatus::ok;
    std::int64_t c = 0;
    while (c < end && status == pl::StepStatus::ok) {
        std::int64_t next = std::min(end, (c / kSampleCycles + 1) * kSampleCycles);
        if (c < half) next = std::min(next, half);
        status = pl::step_across_edges(robot, in, drive, c, next, static_cast<std::uint32_t>(pl::kCpuHz), edges)
                     .status;
        if (status != pl::StepStatus::ok) break;  // the plant stopped inside this interval
        c = next;
        if (c == half) {
            for (std::size_t m = 0; m < pl::kMotorCount; ++m) angle_at_half[m] = robot.motor_angle_rad(m);
        }
        if (c % kSampleCycles == 0 || c == end) append_row(csv, robot, c);
    }

    // --- outputs -------------------------------------------------------------
    const double measured_s = pl::cycles_to_s(end - half);
    auto mean_rpm = [&](std::size_t m) {
        return pl::rad_s_to_rpm((robot.motor_angle_rad(m) - angle_at_half[m]) / measured_s /
                                params.motor[m].gear_ratio);
    };
    const pl::Pose& p = robot.pose();
    const pl::BodyVelocity b = robot.body_velocity();
    nlohmann::json j;
    j["status"] = pl::to_string(status);
    j["mode"] = o.pwm;
    j["duty"] = o.duty;
    j["duty_effective"] = switched ? std::vector<double>{drive.pwm[0].duty(), drive.pwm[1].duty()} : o.duty;
    if (switched) j["ocr"] = {drive.pwm[0].ocr, drive.pwm[1].ocr};
    j["dir"] = o.dir;
    j["seconds"] = o.seconds;
    j["plant_file"] = o.plant_file.empty() ? "(embedded defaults)" : o.plant_file;
    j["t_s"] = robot.time_s();
    j["x_m"] = p.x_m;
    j["y_m"] = p.y_m;
    j["theta_rad"] = p.theta_rad;
    j["v_m_s"] = b.v_m_s;
    j["omega_rad_s"] = b.omega_rad_s;
    j["ia1_A"] = robot.motor_current_A(0);
    j["ia2_A"] = robot.motor_current_A(1);
    j["wheel1_rad_s"] = robot.wheel_speed_rad_s(0);
    j["wheel2_rad_s"] = robot.wheel_speed_rad_s(1);
    j["wheel1_rpm"] = pl::rad_s_to_rpm(robot.wheel_speed_rad_s(0));
    j["wheel2_rpm"] = pl::rad_s_to_rpm(robot.wheel_speed_rad_s(1));
    j["mean_wheel1_rpm_second_half"] = mean_rpm(0);
    j["mean_wheel2_rpm_second_half"] = mean_rpm(1);
    j["vbatt_V"] = robot.battery_voltage_V();
    j["charge_drawn_C"] = robot.charge_drawn_C();
    j["edges1"] = robot.edge_count(0);
    j["edges2"] = robot.edge_count(1);
    write_file_atomic(out_dir / "plant.csv", csv);
    write_file_atomic(out_dir / "summary.json", j.dump(2) + "\n");
    if (status != pl::StepStatus::ok) {
        fmt::print(stderr, "ddmr-hil plant: the plant stopped at t = {} s: {}\n", robot.time_s(),
                   pl::to_string(status));
        return kExitCheckFailed;
    }
    fmt::print("plant: {} s {} run, wheel speeds {:.2f} / {:.2f} RPM (mean of the second half "
               "{:.2f} / {:.2f}), wrote {}\n",
               o.seconds, o.pwm, pl::rad_s_to_rpm(robot.wheel_speed_rad_s(0)),
               pl::rad_s_to_rpm(robot.wheel_speed_rad_s(1)), mean_rpm(0), mean_rpm(1),
               out_dir.string());
    return kExitOk;
}

}  // namespace

Subcommand register_plant_command(CLI::App& app) {
    auto opts = std::make_shared<PlantOptions>();
    CLI::App* sub = app.add_subcommand(
        "plant", "Open-loop run of the plant model (motors, L298, battery, encoders, kinematics)");
    sub->add_option("--duty", opts->duty, "PWM duty of motor 1 (right) and motor 2 (left), 0..1")
        ->required()
        ->delimiter(',')
        ->expected(2)
        ->check(CLI::Range(0.0, 1.0));
    sub->add_option("--dir", opts->dir, "direction pins: F (forward) or R (reverse), per motor")
        ->delimiter(',')
        ->expected(2)
        ->check(CLI::IsMember({"F", "R"}))
        ->capture_default_str();
    sub->add_option("--pwm", opts->pwm, "bridge input model: averaged (duty) or switched (490 Hz pin)")
        ->check(CLI::IsMember({"averaged", "switched"}))
        ->capture_default_str();
    sub->add_option("--seconds", opts->seconds, "simulated time [s], (0, 3600]")
        ->check(CLI::Range(1e-9, 3600.0))
        ->capture_default_str();
    sub->add_option("--plant", opts->plant_file, "plant parameter YAML (default: embedded defaults)")
        ->check(CLI::ExistingFile);
    sub->add_option("--out", opts->out, "output folder")->capture_default_str();
    return Subcommand{sub, [opts] { return run_plant(*opts); }};
}

}  // namespace ddmr::tools
