#pragma once
// Shaft encoder: a function of the motor-shaft angle => one or two output
// levels, and the exact times at which they change.
//
// The thesis robot (ch. 6): a disc with 4 magnets on the motor shaft and one
// Hall sensor, wired to an interrupt pin set to CHANGE. The output toggles at
// every magnet boundary: 8 edges per motor revolution, 8 x 48 = 384 per wheel
// revolution. It has no direction output: turning backwards toggles it just
// the same, and a shaft rocking across one boundary toggles it every time.
//
// Resolution, exactly one of:
//   edges_per_motor_rev : level changes of ONE output per motor-shaft turn
//                         (before the gear); boundary spacing 2 pi / that;
//   edges_per_wheel_rev : level changes of one output per WHEEL turn (e.g. 40
//                         for a 20-slot disc on the wheel shaft); boundary
//                         spacing at the motor shaft 2 pi gear_ratio / that.
// Outputs (`channels`, set by the HIL from the board file):
//   1 (single, OUT) : the shaft angle in units of one spacing, shifted by
//                     `initial_phase`, is floored to a boundary index
//                     j = floor(angle / spacing + phase); every index change
//                     toggles OUT, which starts high.
//   2 (quadrature)  : A and B, each with the spacing above between its own
//                     edges, B a quarter period behind A when the angle
//                     increases (A leads B going forward, B leads A in
//                     reverse). Sub-index j = floor(angle / (spacing / 2) +
//                     2 phase); (A, B) = j mod 4 -> 0: (0, 0), 1: (1, 0),
//                     2: (1, 1), 3: (0, 1). Every change of j is one edge of A
//                     (odd boundaries) or B (even): 4 edges per A period
//                     ("4x"), 2 x edges_per_motor_rev per motor turn. The
//                     levels start as the initial j gives them.
// Each edge's time is solved exactly on the motor's closed-form solution
// (MotorStepper::state_at, or the joint solution's), not interpolated.
//
// Optional (off by default), from a std::mt19937_64 seeded by `seed`:
//   jitter : each reported time moves by N(0, jitter_stddev_s), kept inside
//            the step and after the encoder's previous edge;
//   missed : an edge is lost with probability missed_edge_probability: no
//            report, no toggle of that output (its later edges keep
//            toggling, so its phase flips, as when a sensor misses a pole).
//
// (motor segment) => edges appended to an EdgeBuffer; count; output levels.

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
    /// Level changes of ONE output per motor-shaft turn, before the gear [1]:
    /// even, [2, 4096], or 0 when edges_per_wheel_rev is given instead.
    /// Thesis ch. 6: 4 magnets, both edges = 8.
    int edges_per_motor_rev = 8;
    /// Level changes of one output per wheel turn [1]: even, (0, 1e6], or 0
    /// (not given: edges_per_motor_rev is). E.g. 40 for a 20-slot optical
    /// disc on the wheel shaft, both edges.
    double edges_per_wheel_rev = 0.0;
    double initial_phase = 0.5;           ///< shaft position at angle 0 within one boundary spacing, [0, 1).
    double jitter_stddev_s = 0.0;         ///< [s], [0, 0.001]. 0 = off.
    double missed_edge_probability = 0.0; ///< [0, 0.5]. 0 = off.
    std::uint64_t seed = 1;               ///< generator seed, any value.
    /// Outputs: 1 = single channel (OUT), 2 = quadrature (A, B). Not a YAML
    /// key: the HIL sets it from the board file.
    int channels = 1;
};

/// The YAML keys (not `channels`).
const std::array<Field<HallEncoderParams>, 6>& hall_encoder_fields();
/// Ranges, even edge counts, exactly one resolution key > 0, channels 1 or 2.
void validate(const HallEncoderParams& p, const char* prefix);

/// Angle of the motor shaft between two level changes of one output [rad]:
/// 2 pi / edges_per_motor_rev, or 2 pi gear_ratio / edges_per_wheel_rev.
double boundary_spacing_rad(const HallEncoderParams& p, double gear_ratio);

class HallEncoder {
  public:
    /// `channel` = the motor index (EncoderEdge::channel); `gear_ratio` =
    /// motor turns per wheel turn (for edges_per_wheel_rev).
    HallEncoder(const HallEncoderParams& p, unsigned channel, double gear_ratio);

    /// Back to the initial state (count 0, levels as the shaft angle gives
    /// them, OUT high, generator reseeded) with the shaft at `angle_rad`.
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

    /// Edges reported so far, of all outputs.
    [[nodiscard]] std::uint64_t edge_count() const { return count_; }
    /// The level of output `signal` now (0: OUT or A, 1: B; a single-channel
    /// encoder's signal 1 is always low).
    [[nodiscard]] bool level(unsigned signal = 0) const { return level_[signal & 1U]; }
    /// Boundary spacing of one output [rad] (boundary_spacing_rad).
    [[nodiscard]] double spacing_rad() const { return spacing_rad_; }
    [[nodiscard]] int channels() const { return p_.channels; }

  private:
    [[nodiscard]] std::int64_t index_of(double angle_rad) const;
    /// The output that changes at the boundary below index `boundary`.
    [[nodiscard]] unsigned signal_of(std::int64_t boundary) const;
    /// Reports (or, when missed, drops) the edge of `signal` found at plant time t_s.
    void emit(unsigned signal, double t_s, double step_start_s, double step_end_s, EdgeBuffer& out);

    HallEncoderParams p_;
    unsigned channel_;
    double spacing_rad_;
    double index_step_rad_;  ///< angle between index boundaries: spacing (single) or spacing / 2
    double index_offset_;    ///< initial_phase (single) or 2 initial_phase (quadrature)
    std::int64_t index_ = 0;
    std::array<bool, 2> level_{true, false};
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
        // Boundary between index k-1 and k lies at angle (k - offset) step.
        const std::int64_t boundary = dir > 0 ? index_ + 1 : index_;
        const double angle = (static_cast<double>(boundary) - index_offset_) * index_step_rad_;
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
        emit(signal_of(boundary), step_start_s + seg_t0_s + tau, step_start_s, step_end_s, out);
    }
}

}  // namespace ddmr::plant
