#pragma once
// Hall-effect shaft encoder (thesis ch. 6): a disc with 4 magnets on the motor
// shaft and one Hall sensor, wired to an interrupt pin set to CHANGE. The
// output toggles at every magnet boundary: 8 edges per motor revolution,
// 8 x 48 = 384 per wheel revolution. It has no direction output: turning
// backwards toggles it just the same, and a shaft rocking across one
// boundary toggles it every time.
//
// The level is a function of the shaft angle: the shaft angle in units of
// one boundary spacing (2 pi / edges_per_motor_rev), shifted by
// `initial_phase`, is floored to a boundary index; every index change is an
// edge. Each edge's time is solved exactly on the motor's closed-form
// solution (MotorStepper::state_at), not interpolated linearly.
//
// Optional (off by default), from a std::mt19937_64 seeded by `seed`:
//   jitter : each reported time moves by N(0, jitter_stddev_s), kept inside
//            the step and after the previous edge of the channel;
//   missed : an edge is lost with probability missed_edge_probability: no
//            report, no toggle (later edges keep toggling, so the output's
//            phase flips, as when a sensor misses a pole).
//
// (motor segment) => edges appended to an EdgeBuffer; count; pin level.

#include <array>
#include <cstdint>
#include <cmath>
#include <random>
#include <utility>

#include "plant/encoder_edge.hpp"
#include "plant/motor_stepper.hpp"
#include "plant/param_spec.hpp"
#include "plant/root_find.hpp"

namespace ddmr::plant {

struct HallEncoderParams {
    int edges_per_motor_rev = 8;          ///< even, [2, 4096]. Thesis ch. 6 (4 magnets, both edges).
    double initial_phase = 0.5;           ///< shaft position at angle 0 within one boundary spacing, [0, 1).
    double jitter_stddev_s = 0.0;         ///< [s], [0, 0.001]. 0 = off.
    double missed_edge_probability = 0.0; ///< [0, 0.5]. 0 = off.
    std::uint64_t seed = 1;               ///< generator seed, any value.
};

const std::array<Field<HallEncoderParams>, 5>& hall_encoder_fields();
void validate(const HallEncoderParams& p, const char* prefix);

class HallEncoder {
  public:
    HallEncoder(const HallEncoderParams& p, unsigned channel);

    /// Back to the initial state (count 0, level high, generator reseeded)
    /// with the shaft at `angle_rad`.
    void reset(double angle_rad);

    /// Appends the edges of one motor segment. `step_start_s` is the plant
    /// time at the start of the step (segment times are relative to it),
    /// `step_end_s` the time at its end (bounds for jitter).
    void process(const MotorStepper& motor, const MotorSegment& seg, double step_start_s,
                 double step_end_s, EdgeBuffer& out);

    /// The same for any exact solution: `state_at(tau)` is the motor's state
    /// `tau` seconds into a stretch that starts `seg_t0_s` after the step
    /// start, lasts `seg_duration_s`, turns the shaft from `start_angle_rad`
    /// to `end_angle_rad`, and in which the speed keeps its sign.
    template <class StateAt>
    void process(const StateAt& state_at, double seg_t0_s, double seg_duration_s,
                 double start_angle_rad, double end_angle_rad, double step_start_s,
                 double step_end_s, EdgeBuffer& out);

    /// Changes the missed-edge probability from now on, [0, 0.5] (throws
    /// std::invalid_argument); the generator keeps its state.
    void set_missed_edge_probability(double p);

    [[nodiscard]] std::uint64_t edge_count() const { return count_; }
    [[nodiscard]] bool level() const { return level_; }
    /// Boundary spacing [rad] = 2 pi / edges_per_motor_rev.
    [[nodiscard]] double spacing_rad() const { return spacing_rad_; }

  private:
    [[nodiscard]] std::int64_t index_of(double angle_rad) const;
    /// Reports (or, when missed, drops) the edge found at plant time t_s.
    void emit(double t_s, double step_start_s, double step_end_s, EdgeBuffer& out);

    HallEncoderParams p_;
    unsigned channel_;
    double spacing_rad_;
    std::int64_t index_ = 0;
    bool level_ = true;
    std::uint64_t count_ = 0;
    double last_edge_s_ = 0.0;
    std::mt19937_64 rng_;
    std::normal_distribution<double> jitter_;
    std::bernoulli_distribution missed_;
};

template <class StateAt>
void HallEncoder::process(const StateAt& state_at, double seg_t0_s, double seg_duration_s,
                          double start_angle_rad, double end_angle_rad, double step_start_s,
                          double step_end_s, EdgeBuffer& out) {
    if (!std::isfinite(end_angle_rad)) return;  // the robot reports the divergence
    const std::int64_t target = index_of(end_angle_rad);
    if (target == index_) return;
    const int dir = target > index_ ? 1 : -1;  // w keeps its sign within a stretch
    while (index_ != target) {
        // Boundary between index k-1 and k lies at angle (k - phase) spacing.
        const std::int64_t boundary = dir > 0 ? index_ + 1 : index_;
        const double angle = (static_cast<double>(boundary) - p_.initial_phase) * spacing_rad_;
        index_ += dir;
        auto f = [&](double tau) {
            const DcMotorState s = state_at(tau);
            return std::pair<double, double>{s.angle_rad - angle, s.speed_rad_s};
        };
        // First guess: the shaft turning at a constant rate over the stretch
        // (Newton then corrects for the change of speed).
        const double guess =
            seg_duration_s * (angle - start_angle_rad) / (end_angle_rad - start_angle_rad);
        const double tau = find_root(f, 0.0, seg_duration_s, dir > 0 ? -1.0 : 1.0, guess);
        emit(step_start_s + seg_t0_s + tau, step_start_s, step_end_s, out);
    }
}

}  // namespace ddmr::plant
