// `ddmr-hil sim [--model ideal|firmware] [--case 1|2 | --circle R,T | --line x|y]
//               [--fidelity a,b,...] [--kx K --ky K --kw K --vref V --wref W]
//               [--duration S] [--period-ms P] [--plant-step S]
//               [--plant FILE|kinematic] [--pwm averaged|switched] [--out DIR]`
//
// Every option is checked, and the configuration validated, before the output
// folder is touched; a bad value gives one line naming the option and the
// value, exit code 2. The wall time is measured here, around the model.
#include "sim_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iterator>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/hostsim_json.hpp"
#include "common/plant_option.hpp"
#include "common/sim_csv.hpp"
#include "common/truth_csv.hpp"
#include "exit_codes.hpp"
#include "hil/eeprom_log.hpp"
#include "hil/eeprom_port.hpp"
#include "plant/params_yaml.hpp"
#include "tools/hostsim/host_sim.hpp"

namespace ddmr::tools {

namespace {

namespace hs = ddmr::hostsim;

/// `--plant kinematic` selects the kinematic robot instead of a parameter file.

struct SimCli {
    std::string model = "ideal";
    int case_number = 1;
    std::vector<double> circle;
    std::string line;
    std::string fidelity;
    std::optional<double> kx, ky, kw, vref, wref;
    std::optional<double> duration_s;
    double period_ms = 10.0;
    std::optional<double> plant_step_s;
    std::string plant;
    std::string pwm = "averaged";
    std::string out;
    CLI::Option* fidelity_opt = nullptr;
    CLI::Option* circle_opt = nullptr;
    CLI::Option* line_opt = nullptr;
};

/// Everything the run needs, checked.
struct SimPlan {
    hs::SimConfig config;
    std::string plant_source;
    std::filesystem::path out_dir;
};

SimPlan plan_of(const SimCli& o) {
    SimPlan p;
    hs::SimConfig& c = p.config;
    c.model = hs::parse_model(o.model);
    if (o.circle_opt->count() > 0) {
        if (o.circle.size() != 2 || !(o.circle[0] > 0.0) || !(o.circle[1] > 0.0)) {
            throw std::invalid_argument(fmt::format("--circle {}: needs R,T with radius R > 0 m and lap time T > 0 s",
                                                    fmt::join(o.circle, ",")));
        }
        c.case_spec = hs::circle_case(o.circle[0], o.circle[1]);
    } else if (o.line_opt->count() > 0) {
        c.case_spec = hs::line_step_case(o.line == "x" ? hs::StepAxis::x : hs::StepAxis::y);
    } else {
        c.case_spec = hs::firmware_case(o.case_number);
    }
    if (o.fidelity_opt->count() > 0) {
        hs::Fidelity f;
        try {
            f = hs::Fidelity::parse(o.fidelity);
        } catch (const std::invalid_argument& e) {
            throw std::invalid_argument(fmt::format("--fidelity {}: {}", o.fidelity, e.what()));
        }
        if (c.model == hs::Model::firmware && !f.is_all()) {
            throw std::invalid_argument(fmt::format(
                "--fidelity {}: only with --model ideal (--model firmware has every switch on)", o.fidelity));
        }
        c.fidelity = f;
    } else {
        c.fidelity = c.model == hs::Model::firmware ? hs::Fidelity::all() : hs::Fidelity::none();
    }
    c.gains = hs::default_gains(c.case_spec);
    if (o.kx) c.gains.kx = *o.kx;
    if (o.ky) c.gains.ky = *o.ky;
    if (o.kw) c.gains.kw = *o.kw;
    if (o.vref) c.gains.vref_m_s = *o.vref;
    if (o.wref) c.gains.wref_rad_s = *o.wref;
    c.duration_s = o.duration_s ? *o.duration_s : c.case_spec.duration_s;
    c.period_s = o.period_ms * 1e-3;
    c.pwm = o.pwm == "switched" ? hs::PwmModel::switched : hs::PwmModel::averaged;

    const PlantChoice plant_choice = resolve_plant_option(o.plant);
    c.kinematic_plant = plant_choice.kinematic;
    c.plant = plant_choice.params;
    p.plant_source = plant_choice.source;
    c.plant_step_s = o.plant_step_s ? *o.plant_step_s : c.plant.stepper.max_step_s;

    if (c.kinematic_plant) {
        if (c.model != hs::Model::ideal) {
            throw std::invalid_argument("--plant kinematic: only with --model ideal");
        }
        for (hs::FidelitySwitch s : {hs::FidelitySwitch::encoder_odometry, hs::FidelitySwitch::feedforward_constants,
                                     hs::FidelitySwitch::pwm_quantisation}) {
            if (c.fidelity.has(s)) {
                throw std::invalid_argument(fmt::format("--plant kinematic: --fidelity {} needs the motor plant",
                                                        hs::to_string(s)));
            }
        }
        if (c.pwm != hs::PwmModel::averaged) {
            throw std::invalid_argument("--plant kinematic: the kinematic robot has no PWM (--pwm averaged)");
        }
    }
    if (o.duration_s && c.fidelity.has(hs::FidelitySwitch::loop_period)) {
        const double n = std::round(*o.duration_s / 0.01);
        if (!(n >= 1.0) || std::abs(n * 0.01 - *o.duration_s) > 1e-9) {
            throw std::invalid_argument(fmt::format(
                "--duration {}: with loop_period the firmware runs whole 0.01 s iterations", *o.duration_s));
        }
    }
    hs::validate(c);  // what is left: combinations named in the message

    p.out_dir = o.out.empty() ? std::filesystem::path("out") /
                                    fmt::format("sim-{}-{}", c.case_spec.name, hs::to_string(c.model))
                              : std::filesystem::path(o.out);
    return p;
}


/// The log in hil::eeprom_log_csv's format. Byte logs go through the HIL's
/// own decoder (an erased EEPROM image holding the sketch's bytes).
std::string eeprom_csv(const hs::SimResult& r) {
    std::vector<hil::EepromLogSample> samples;
    if (r.eeprom_quantised) {
        hil::EepromImage image = hil::EepromPort::erased(hil::atmega328p_mcu());  // the thesis robot's Uno
        std::vector<double> times;
        for (const hs::EepromLogEntry& e : r.eeprom_log) {
            const auto addr = static_cast<std::size_t>(e.sample) * hil::eeprom_log::kAddressStride;
            image[addr] = e.x_byte;
            image[addr + hil::eeprom_log::kYOffset] = e.y_byte;
            times.push_back(e.t_s);
        }
        samples = hil::decode_eeprom_log(image, static_cast<int>(r.eeprom_log.size()), times);
    } else {
        for (const hs::EepromLogEntry& e : r.eeprom_log) {
            hil::EepromLogSample s;
            s.sample = e.sample;
            s.t_s = e.t_s;
            s.x_m = e.x_m;
            s.y_m = e.y_m;
            samples.push_back(s);
        }
    }
    return hil::eeprom_log_csv(samples);
}



int run_sim(const SimCli& o) {
    const SimPlan plan = plan_of(o);
    const hs::SimConfig& c = plan.config;
    prepare_output_dir(plan.out_dir);

    const auto wall_start = std::chrono::steady_clock::now();
    const hs::SimResult r = hs::simulate(c);
    const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

    nlohmann::json j;
    j["model"] = hs::to_string(c.model);
    j["fidelity"] = c.fidelity.names();
    j["case"] = case_json(c.case_spec);
    j["gains"] = gains_json(c.gains);
    j["gains_effective"] = gains_json(r.effective_gains);
    j["plant"] = plan.plant_source;
    j["pwm"] = hs::to_string(c.pwm);
    j["duration_s"] = c.duration_s;
    j["period_s"] = c.period_s;
    j["plant_step_s"] = c.plant_step_s;
    j["end_time_s"] = r.end_time_s;
    j["controller_end_time_s"] = r.controller_end_time_s;
    j["end_pose"] = {{"x_m", r.end_pose.x_m}, {"y_m", r.end_pose.y_m}, {"theta_rad", r.end_pose.theta_rad}};
    j["end_estimate"] = {{"x_m", r.end_estimate.x_m},
                         {"y_m", r.end_estimate.y_m},
                         {"theta_rad", r.end_estimate.theta_rad}};
    j["goal_end"] = {{"x_m", r.goal_end_x_m}, {"y_m", r.goal_end_y_m}};
    j["end_error_m"] = std::hypot(r.goal_end_x_m - r.end_pose.x_m, r.goal_end_y_m - r.end_pose.y_m);
    j["control_iterations"] = r.control_iterations;
    j["plant_steps"] = r.plant_steps;
    j["eeprom_log"] = {{"written", r.eeprom_logged},
                       {"quantised", r.eeprom_quantised},
                       {"samples", r.eeprom_log.size()},
                       {"truncated", r.eeprom_truncated}};
    j["status"] = plant::to_string(r.status);
    if (r.status != plant::StepStatus::ok) j["status_at_s"] = r.status_at_s;
    j["wall_time_s"] = wall_s;

    write_file_atomic(plan.out_dir / "sim.csv", sim_csv(r));
    const std::filesystem::path log_path = plan.out_dir / "eeprom_log.csv";
    if (r.eeprom_logged) {
        write_file_atomic(log_path, eeprom_csv(r));
    } else {
        std::error_code ec;
        std::filesystem::remove(log_path, ec);  // no stale log from an earlier run
    }
    write_file_atomic(plan.out_dir / "summary.json", j.dump(2) + "\n");

    if (r.status != plant::StepStatus::ok) {
        fmt::print(stderr, "ddmr-hil sim: the plant stopped at t = {} s: {}\n", r.status_at_s,
                   plant::to_string(r.status));
        return kExitCheckFailed;
    }
    fmt::print("sim: {} {} ({}), {:.3f} s: end ({:.4f}, {:.4f}) m, goal ({:.4f}, {:.4f}) m, "
               "{} iterations, wall {:.3f} s, wrote {}\n",
               c.case_spec.name, hs::to_string(c.model), c.fidelity.to_string(), r.end_time_s, r.end_pose.x_m,
               r.end_pose.y_m, r.goal_end_x_m, r.goal_end_y_m, r.control_iterations, wall_s,
               plan.out_dir.string());
    return kExitOk;
}

}  // namespace

Subcommand register_sim_command(CLI::App& app) {
    auto o = std::make_shared<SimCli>();
    CLI::App* sub = app.add_subcommand(
        "sim", "Host reference simulation: the thesis's closed loop (Kanayama law, eq. 17 feed-forward) on "
               "the HIL's plant model, ideal or as the firmware computes it (docs/hostsim.md)");
    sub->add_option("--model", o->model, "ideal (the thesis's idealisation) or firmware (every fidelity switch on)")
        ->check(CLI::IsMember({"ideal", "firmware"}))
        ->capture_default_str();
    auto* case_opt = sub->add_option("--case", o->case_number,
                                     "the firmware's case: 1 = 0.6 m circle in 12 s, 2 = 0.4 m in 8 s")
                         ->check(CLI::IsMember({1, 2}))
                         ->capture_default_str();
    o->circle_opt = sub->add_option("--circle", o->circle, "a circle about the origin: radius [m], lap time [s]")
                        ->delimiter(',')
                        ->expected(2);
    o->line_opt = sub->add_option("--line", o->line,
                                  "appendix A2's straight line at 0.5 m/s with a 20 cm step at 10 s along x or y")
                      ->check(CLI::IsMember({"x", "y"}));
    case_opt->excludes(o->circle_opt)->excludes(o->line_opt);
    o->circle_opt->excludes(o->line_opt);
    std::string switch_list;
    for (const char* n : hs::fidelity_switch_names()) switch_list += std::string(switch_list.empty() ? "" : ", ") + n;
    o->fidelity_opt = sub->add_option("--fidelity", o->fidelity,
                                      "with --model ideal: switches to turn on, comma-separated (" + switch_list +
                                          "; or all, none)");
    sub->add_option("--kx", o->kx, "K_x [1/s] (default 1.1, as the sketch writes it)")->check(CLI::Range(0.0, 1000.0));
    sub->add_option("--ky", o->ky, "K_y (default 6)")->check(CLI::Range(0.0, 1000.0));
    sub->add_option("--kw", o->kw, "K_w (default 8)")->check(CLI::Range(0.0, 1000.0));
    sub->add_option("--vref", o->vref,
                    "feed-forward v_g [m/s] (default: 0.2 for cases 1, 2; the goal's speed otherwise)")
        ->check(CLI::Range(-10.0, 10.0));
    sub->add_option("--wref", o->wref,
                    "feed-forward w_g [rad/s] (default: 0.2 for cases 1, 2; the goal's rate otherwise)")
        ->check(CLI::Range(-100.0, 100.0));
    sub->add_option("--duration", o->duration_s,
                    "run length on the controller's clock [s] (default: the case's; 12, 8, T, 20)")
        ->check(CLI::Range(1e-6, 3600.0));
    sub->add_option("--period-ms", o->period_ms,
                    "control period with the loop_period switch [ms] (the HIL measures ~10.44)")
        ->check(CLI::Range(0.1, 1000.0))
        ->capture_default_str();
    sub->add_option("--plant-step", o->plant_step_s,
                    "plant step [s] (default: the plant's max_step_s, 1e-4); the ideal control runs at this rate")
        ->check(CLI::Range(62.5e-9, 0.01));
    sub->add_option("--plant", o->plant, "plant parameter YAML (default: embedded), or 'kinematic' (ideal only)");
    sub->add_option("--pwm", o->pwm, "bridge input: averaged (duty) or switched (the 490 Hz waveform)")
        ->check(CLI::IsMember({"averaged", "switched"}))
        ->capture_default_str();
    sub->add_option("--out", o->out, "output folder [default: out/sim-<case>-<model>, e.g. out/sim-case1-ideal]");
    return Subcommand{sub, [o] { return run_sim(*o); }};
}

}  // namespace ddmr::tools
