#include "plant/robot.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace ddmr::plant {

namespace {
bool finite(const RobotState& s) {
    // v * 0 is 0 for a finite v and NaN for an infinite or NaN one, so the
    // sum is 0 exactly when every value is finite (no branch per value).
    double zero = 0.0 * s.t_s + 0.0 * s.battery.charge_drawn_C + 0.0 * s.pose.x_m +
                  0.0 * s.pose.y_m + 0.0 * s.pose.theta_rad;
    for (const DcMotorState& m : s.motor) {
        zero += 0.0 * m.current_A + 0.0 * m.speed_rad_s + 0.0 * m.angle_rad;
    }
    return zero == 0.0;
}
/// A motor whose shaft is held: stiction without bound, so it stays in the
/// stuck regime (w = 0, L dI/dt = V - R I) whatever the current.
DcMotorParams held_shaft(DcMotorParams p) {
    p.coulomb_friction_N_m = std::numeric_limits<double>::infinity();
    return p;
}
}  // namespace

const char* to_string(StepStatus s) {
    switch (s) {
        case StepStatus::ok: return "ok";
        case StepStatus::bad_input: return "bad_input";
        case StepStatus::diverged: return "diverged";
        case StepStatus::edge_overflow: return "edge_overflow";
    }
    return "unknown";
}

RobotParams Robot::validated(const RobotParams& p) {
    validate(p);
    return p;
}

Robot::Robot(const RobotParams& params)
    : params_(validated(params)),
      stepper_{MotorStepper(params_.motor[0]), MotorStepper(params_.motor[1])},
      held_{MotorStepper(held_shaft(params_.motor[0])), MotorStepper(held_shaft(params_.motor[1]))},
      encoder_{HallEncoder(params_.encoder[0], 0, params_.motor[0].gear_ratio),
               HallEncoder(params_.encoder[1], 1, params_.motor[1].gear_ratio)},
      coupled_(params_.motor[0], params_.motor[1]) {
    reset();
}

void Robot::reset(const Pose& pose) {
    state_ = RobotState{};
    state_.pose = pose;
    for (std::size_t m = 0; m < kMotorCount; ++m) encoder_[m].reset(0.0);
    status_ = StepStatus::ok;
    diverged_at_s_ = 0.0;
    contact_.reset();
    contact_held_ = {false, false};
}

void Robot::set_faults(const RobotFaults& faults) {
    validate(faults);
    faults_ = faults;
}

void Robot::displace(const Pose& delta) {
    state_.pose.x_m += delta.x_m;
    state_.pose.y_m += delta.y_m;
    state_.pose.theta_rad += delta.theta_rad;
}

void Robot::set_missed_edge_probability(std::size_t m, double p) {
    if (m >= kMotorCount) throw std::invalid_argument("encoder index " + std::to_string(m) + " out of range");
    encoder_[m].set_missed_edge_probability(p);
}

BodyVelocity Robot::body_velocity() const {
    return plant::body_velocity(params_.kinematics, wheel_speed_rad_s(0), wheel_speed_rad_s(1));
}

double Robot::wheel_speed_rad_s(std::size_t m) const {
    return plant::wheel_speed_rad_s(params_.motor[m], state_.motor[m].speed_rad_s);
}

double Robot::supply_current_A(std::size_t m) const {
    const BridgeInput& b = input_.bridge[m];
    const double i = state_.motor[m].current_A;
    if (input_.mode == DriveMode::averaged) {
        const double sign = b.forward ? 1.0 : -1.0;
        return sign * b.duty * i;
    }
    switch (b.state) {
        case BridgeState::forward: return i;
        case BridgeState::reverse: return -i;
        case BridgeState::brake: return 0.0;  // the winding is shorted inside the bridge
        case BridgeState::coast: break;
    }
    return -std::abs(i);  // bridge off: the current returns through the diodes
}

double Robot::supply_current_A() const { return supply_current_A(0) + supply_current_A(1); }

double Robot::battery_voltage_V() const {
    if (faults_.source_V) {
        return std::max(*faults_.source_V - params_.battery.internal_resistance_ohm * supply_current_A(), 0.0);
    }
    return terminal_voltage_V(params_.battery, state_.battery, supply_current_A());
}

bool Robot::input_valid() const {
    for (const BridgeInput& b : input_.bridge) {
        if (!(b.duty >= 0.0 && b.duty <= 1.0)) return false;  // also rejects NaN
        if (!(b.brake >= 0.0 && b.brake <= 1.0)) return false;
        if (static_cast<unsigned>(b.state) > static_cast<unsigned>(BridgeState::brake)) return false;
    }
    return true;
}

bool Robot::substep(double h, EdgeBuffer& edges) {
    const RobotState before = state_;
    // The battery, eq. (19), couples both motors: V_b = V_0 - k AH - R_b (I_s1 + I_s2).
    // Each motor's own share of the R_b drop is solved exactly with it (as a
    // series resistance, bridge_driver.hpp); the other motor's supply current
    // and the charge term are held over the step at their midpoint values
    // by a predictor-corrector:
    //   predict: hold them at the start of the step -> mean supply currents;
    //   correct: V_0 - k (q + dq/2)/3600 and the mean currents, solve again.
    // Holding start values alone is first order in h; this is second order.
    // When the corrected voltages differ from the predicted ones by less than
    // kAcceptV (steady running), the prediction is kept: one solve, not two.
    constexpr double kAcceptV = 1e-9;
    const BatteryParams& bp = params_.battery;
    const double rb = bp.internal_resistance_ohm;
    std::array<double, kMotorCount> other_supply_A{supply_current_A(1), supply_current_A(0)};
    double source_V = faults_.source_V ? *faults_.source_V : source_voltage_V(bp, before.battery);
    for (int pass = 0; pass < 2; ++pass) {
        double supply_charge_C = 0.0;
        std::array<double, kMotorCount> mean_supply_A{};
        for (std::size_t m = 0; m < kMotorCount; ++m) {
            const MotorTerminal u = terminal(bridge_params(params_, m), input_.mode, input_.bridge[m],
                                             source_V - rb * other_supply_A[m], rb);
            DcMotorState x = before.motor[m];
            if (held(m)) {
                // Held shaft: it stops at once and stays stuck (unbounded stiction).
                x.speed_rad_s = 0.0;
                held_[m].advance(x, u, h, scratch_[m]);
            } else {
                stepper_[m].advance(x, u, h, scratch_[m]);
            }
            supply_charge_C += scratch_[m].supply_charge_C;
            mean_supply_A[m] = scratch_[m].supply_charge_C / h;
            state_.motor[m] = x;
        }
        state_.battery.charge_drawn_C = before.battery.charge_drawn_C + supply_charge_C;  // eq. (18)
        if (pass == 1) break;
        BatteryState mid = before.battery;
        mid.charge_drawn_C += 0.5 * supply_charge_C;
        const double mid_source_V = faults_.source_V ? *faults_.source_V : source_voltage_V(bp, mid);
        const std::array<double, kMotorCount> mid_other_A{mean_supply_A[1], mean_supply_A[0]};
        double change_V = std::abs(mid_source_V - source_V);
        for (std::size_t m = 0; m < kMotorCount; ++m) {
            change_V = std::max(change_V, rb * std::abs(mid_other_A[m] - other_supply_A[m]));
        }
        if (!(change_V > kAcceptV)) break;  // also stops on NaN (caught below)
        source_V = mid_source_V;
        other_supply_A = mid_other_A;
    }
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        if (!std::isfinite(state_.motor[m].angle_rad)) continue;  // caught below
        if (held(m)) continue;                                      // no rotation, no edges
        const MotorStepResult& r = scratch_[m];
        for (std::size_t k = 0; k < r.segment_count; ++k) {
            encoder_[m].process(stepper_[m], r.segments[k], before.t_s, before.t_s + h, edges);
        }
    }
    return finish_substep(before, h);
}

bool Robot::finish_substep(const RobotState& before, double h) {
    std::array<double, kMotorCount> wheel_turn_rad{};
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        // x traction / gear ratio: that factor does not depend on the state,
        // so a multiplication keeps a division off the update's critical path.
        const double wheel_per_motor = faults_.traction[m] / params_.motor[m].gear_ratio;
        wheel_turn_rad[m] = (state_.motor[m].angle_rad - before.motor[m].angle_rad) * wheel_per_motor;
    }
    advance_exact_arc(params_.kinematics, state_.pose, wheel_turn_rad[0], wheel_turn_rad[1],
                      state_.heading);
    state_.t_s = before.t_s + h;
    if (!finite(state_)) {
        diverged_at_s_ = before.t_s;
        state_ = before;
        status_ = StepStatus::diverged;
        return false;
    }
    return true;
}

double Robot::joint_substep(double h, EdgeBuffer& edges) {
    if (held(0) || held(1)) return 0.0;
    const BatteryParams& bp = params_.battery;
    const double source_V = faults_.source_V ? *faults_.source_V : source_voltage_V(bp, state_.battery);
    std::array<CoupledTerminal, kMotorCount> u{};
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        const MotorTerminal t = terminal(bridge_params(params_, m), input_.mode, input_.bridge[m], source_V);
        u[m] = coupled_terminal(t, state_.motor[m].current_A);
    }
    std::array<DcMotorState, kMotorCount> x = state_.motor;
    double supply_charge_C = 0.0;
    const double done = coupled_.advance(x, u, bp.internal_resistance_ohm, h, joint_, supply_charge_C);
    if (!(done > 0.0)) return 0.0;
    const RobotState before = state_;
    state_.motor = x;
    state_.battery.charge_drawn_C += supply_charge_C;  // eq. (18)
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        if (!std::isfinite(x[m].angle_rad)) continue;  // caught below
        encoder_[m].process([&](double tau) { return coupled_.state_at(joint_, m, tau); }, 0.0, done,
                            before.motor[m].angle_rad, x[m].angle_rad, before.t_s,
                            before.t_s + done, edges);
    }
    return finish_substep(before, done) ? done : -1.0;
}

bool Robot::open_circuit(std::size_t m) const {
    return input_.bridge[m].state == BridgeState::coast && state_.motor[m].current_A == 0.0;
}

bool Robot::both_coasting() const {
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        if (!open_circuit(m) || held(m)) return false;
    }
    return true;
}

bool Robot::coast_substep(double h, EdgeBuffer& edges) {
    // No current flows, so the battery is idle (no charge drawn) and the
    // motors do not interact: each one's exact coasting solution is the step.
    const RobotState before = state_;
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        MotorSegment& seg = scratch_[m].segments[0];
        seg.t0_s = 0.0;
        stepper_[m].coast(before.motor[m], h, seg);
        state_.motor[m] = seg.end;  // stopped early: it stays stopped
        encoder_[m].process(stepper_[m], seg, before.t_s, before.t_s + h, edges);
    }
    return finish_substep(before, h);
}

bool Robot::battery_coupled() const {
    // Switched mode only (averaged mode never splits a step into pieces).
    if (params_.battery.internal_resistance_ohm == 0.0) return false;
    for (std::size_t m = 0; m < kMotorCount; ++m) {
        // No supply current all step: open circuit, or the winding shorted.
        if (open_circuit(m) || input_.bridge[m].state == BridgeState::brake) return false;
    }
    return true;
}

StepResult Robot::step(double dt_s, EdgeBuffer& edges) {
    if (status_ == StepStatus::diverged) return {StepStatus::diverged, state_.t_s};
    if (!(dt_s > 0.0 && dt_s <= 10.0) || !input_valid()) {
        return {StepStatus::bad_input, state_.t_s};
    }
    const std::size_t first = edges.size();
    const std::uint64_t dropped_before = edges.dropped();
    const bool walls = world_ != nullptr && !world_->walls.empty();
    const RobotState before_step = walls ? state_ : RobotState{};
    const double t_end = state_.t_s + dt_s;
    const double max_h = params_.stepper.max_step_s;
    // Equal internal steps; a dt within the limit is used as given, so the
    // motor discretisation cache hits when the caller repeats a dt.
    const double n = dt_s <= max_h ? 1.0 : std::ceil(dt_s / max_h);
    const double h = dt_s / n;
    const auto count = static_cast<long>(n);
    const double event_h = params_.stepper.event_step_s;
    for (long k = 0; k < count; ++k) {
        if (input_.mode == DriveMode::averaged) {
            // Averaged: the supply currents are continuous, so holding the
            // coupling at its midpoint value is second order and the motor
            // by motor solution is as good as the joint one (halving test:
            // 1e-10 m); it also avoids a new eigendecomposition per duty.
            if (!substep(h, edges)) return {StepStatus::diverged, state_.t_s};
            continue;
        }
        double left = h;
        while (left > 0.0) {
            if (both_coasting()) {
                if (!coast_substep(left, edges)) return {StepStatus::diverged, state_.t_s};
                break;
            }
            // Both motors exactly, up to the step's end or the first regime change.
            const double done = joint_substep(left, edges);
            if (done < 0.0) return {StepStatus::diverged, state_.t_s};
            if (done > 0.0) {
                left = done < left ? left - done : 0.0;
                continue;
            }
            // A motor is stuck or open-circuit: motor by motor for the rest of
            // the step, in pieces short enough for the held battery coupling
            // (one piece when one motor draws no current: then it is exact).
            const double pieces = battery_coupled() && left > event_h ? std::ceil(left / event_h) : 1.0;
            const double hp = left / pieces;
            for (long j = 0; j < static_cast<long>(pieces); ++j) {
                if (!substep(hp, edges)) return {StepStatus::diverged, state_.t_s};
            }
            left = 0.0;
        }
    }
    state_.t_s = t_end;
    if (walls) resolve_contact(before_step);
    // Merge the two channels' edges of this step by time (insertion sort: a
    // handful of edges, already sorted per channel; no allocation).
    EncoderEdge* e = edges.data();
    for (std::size_t i = first + 1; i < edges.size(); ++i) {
        const EncoderEdge key = e[i];
        std::size_t j = i;
        while (j > first && e[j - 1].t_s > key.t_s) {
            e[j] = e[j - 1];
            --j;
        }
        e[j] = key;
    }
    const StepStatus s =
        edges.dropped() != dropped_before ? StepStatus::edge_overflow : StepStatus::ok;
    return {s, state_.t_s};
}

}  // namespace ddmr::plant
