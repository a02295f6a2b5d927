#include "hil/plant_coupler.hpp"

#include "hil/parts/part_set.hpp"

#include <sim_avr.h>
#include <sim_cycle_timers.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "plant/drive_stepper.hpp"

namespace ddmr::hil {

CouplerConfig resolved(const CouplerConfig& config, uint32_t clock_hz) {
    CouplerConfig c = config;
    if (c.step_cycles == 0) c.step_cycles = s_to_cycles(CouplerConfig::kDefaultStepS, clock_hz);
    if (c.truth_period_cycles == 0) c.truth_period_cycles = s_to_cycles(CouplerConfig::kDefaultTruthPeriodS, clock_hz);
    return c;
}

PlantCoupler::PlantCoupler(AvrCore& core, plant::Robot& robot, MotorDriverReader& reader,
                           EncoderInjector& injector, const CouplerConfig& config, PartSet* parts)
    : core_(core),
      robot_(robot),
      reader_(reader),
      injector_(injector),
      config_(resolved(config, core.clock_hz())),
      parts_(parts) {
    if (config_.step_cycles == 0) throw std::invalid_argument("coupling step must be >= 1 cycle");
    if (config_.truth_period_cycles == 0 || config_.truth_period_cycles % config_.step_cycles != 0) {
        throw std::invalid_argument("ground-truth period " + std::to_string(config_.truth_period_cycles) +
                                    " cycles is not a positive multiple of the coupling step " +
                                    std::to_string(config_.step_cycles));
    }
    start_cycle_ = core_.cycle();
    next_boundary_ = start_cycle_;
    avr_cycle_timer_register(core_.raw(), 0, &PlantCoupler::on_step, this);
    // A step reads the driver inputs' recorded waveforms, and its observers
    // read globals: over skipped passes that write neither (fast-forward
    // verifies that they wrote no I/O), it may run at its own cycle inside
    // the jump; what it schedules then bounds the jump.
    core_.allow_replay({&PlantCoupler::on_step, this, [](const LoopSpan& s) { return s.writes_only_own_stack(); },
                        ReplayableTimer::Runs::kAtOwnCycle});
    // An AVR reset cancels every cycle timer: the plant steps on from the
    // boundary it was due at (it has already advanced up to there).
    core_.add_reset_listener(this, [this] {
        if (status_ != plant::StepStatus::ok) return;
        const Cycles now = core_.cycle();
        avr_cycle_timer_register(core_.raw(), next_boundary_ > now ? next_boundary_ - now : 0, &PlantCoupler::on_step,
                                 this);
    });
}

PlantCoupler::~PlantCoupler() {
    core_.forget_replay(this);
    core_.remove_reset_listener(this);
    avr_cycle_timer_cancel(core_.raw(), &PlantCoupler::on_step, this);
}

uint64_t PlantCoupler::on_step(struct avr_t* /*avr*/, uint64_t when, void* param) {
    auto* self = static_cast<PlantCoupler*>(param);
    self->step(when);
    if (self->status_ != plant::StepStatus::ok) return 0;
    self->next_boundary_ = when + self->config_.step_cycles;
    return self->next_boundary_;
}

void PlantCoupler::step(Cycles boundary) {
    reader_.advance_to(boundary);
    if (const auto change = reader_.take_first_change()) {
        max_latency_ = std::max(max_latency_, boundary > *change ? boundary - *change : 0);
    }
    plant::RobotInput input;
    input.mode = config_.mode;
    for (std::size_t m = 0; m < 2; ++m) input.bridge[m] = reader_.input_at(m, boundary);
    if ((boundary - start_cycle_) % config_.truth_period_cycles == 0) sample_truth(boundary, input);
    if (step_listener_) step_listener_(boundary, boundary + config_.step_cycles);
    advance(boundary, boundary + config_.step_cycles, input);
    ++steps_;
    if (parts_ != nullptr) parts_->on_plant_step(boundary + config_.step_cycles);
    if (hook_) hook_(boundary);
}

namespace {

/// The driver inputs' decoded waveforms, as the plant stepper reads them.
class ReaderWaveforms final : public plant::DriveWaveforms {
public:
    explicit ReaderWaveforms(const MotorDriverReader& reader) : reader_(reader) {}
    [[nodiscard]] plant::BridgeState state_at(std::size_t m, std::int64_t cycle) const override {
        return reader_.state_at(m, static_cast<Cycles>(cycle));
    }
    [[nodiscard]] std::int64_t next_change_after(std::size_t m, std::int64_t cycle) const override {
        const Cycles next = reader_.next_change_after(m, static_cast<Cycles>(cycle));
        return next >= static_cast<Cycles>(kNever) ? kNever : static_cast<std::int64_t>(next);
    }

private:
    const MotorDriverReader& reader_;
};

}  // namespace

void PlantCoupler::advance(Cycles from, Cycles to, plant::RobotInput& input) {
    const ReaderWaveforms waves(reader_);
    const uint32_t clock_hz = core_.clock_hz();
    const plant::DriveStepResult r = plant::step_across_edges(
        robot_, input, waves, static_cast<std::int64_t>(from), static_cast<std::int64_t>(to), clock_hz, edges_,
        [&](std::int64_t piece_start, const plant::EdgeBuffer& edges) {
            const auto t = static_cast<Cycles>(piece_start);
            for (const plant::EncoderEdge& e : edges) {
                // Plant time is AVR time (both start at reset); never in the past.
                const auto c = static_cast<Cycles>(std::llround(e.t_s * static_cast<double>(clock_hz)));
                injector_.schedule(e.channel, e.signal, std::max(c, t), e.level);
            }
        });
    plant_steps_ += r.pieces;
    if (r.status != plant::StepStatus::ok) {
        status_ = r.status;
        failed_at_s_ = r.t_s;
        core_.request_stop();
    }
}

void PlantCoupler::sample_truth(Cycles boundary, const plant::RobotInput& input) {
    if (!sink_) return;
    TruthSample s = truth_sample_of(robot_, boundary);
    s.t_s = cycles_to_s(boundary, core_.clock_hz());  // AVR time
    s.duty1 = input.bridge[0].duty;  // the drive of the interval that starts here
    s.duty2 = input.bridge[1].duty;
    s.dir1 = input.bridge[0].forward;
    s.dir2 = input.bridge[1].forward;
    sink_(s);
}

TruthSample truth_sample_of(const plant::Robot& robot, Cycles cycle) {
    TruthSample s;
    s.cycle = cycle;
    s.t_s = robot.time_s();
    const plant::Pose& p = robot.pose();
    s.x_m = p.x_m;
    s.y_m = p.y_m;
    s.theta_rad = p.theta_rad;
    const plant::BodyVelocity v = robot.body_velocity();
    s.v_m_s = v.v_m_s;
    s.omega_rad_s = v.omega_rad_s;
    s.ia1_A = robot.motor_current_A(0);
    s.ia2_A = robot.motor_current_A(1);
    s.wheel1_rad_s = robot.wheel_speed_rad_s(0);
    s.wheel2_rad_s = robot.wheel_speed_rad_s(1);
    s.vbatt_V = robot.battery_voltage_V();
    s.edges1 = robot.edge_count(0);
    s.edges2 = robot.edge_count(1);
    s.duty1 = robot.input().bridge[0].duty;
    s.duty2 = robot.input().bridge[1].duty;
    s.dir1 = robot.input().bridge[0].forward;
    s.dir2 = robot.input().bridge[1].forward;
    return s;
}

}  // namespace ddmr::hil
