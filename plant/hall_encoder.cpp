#include "plant/hall_encoder.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>


namespace ddmr::plant {

const std::array<Field<HallEncoderParams>, 5>& hall_encoder_fields() {
    using P = HallEncoderParams;
    static const std::array<Field<P>, 5> table{{
        {"edges_per_motor_rev", "1", Range{2.0, 4096.0, true, true}, &P::edges_per_motor_rev},
        {"initial_phase", "1", Range{0.0, 1.0, true, false}, &P::initial_phase},
        {"jitter_stddev_s", "s", non_negative(1e-3), &P::jitter_stddev_s},
        {"missed_edge_probability", "1", non_negative(0.5), &P::missed_edge_probability},
        {"seed", "1", Range{}, &P::seed},
    }};
    return table;
}

void validate(const HallEncoderParams& p, const char* prefix) {
    validate_fields(p, hall_encoder_fields(), prefix);
    if (p.edges_per_motor_rev % 2 != 0) {
        throw std::invalid_argument(std::string("invalid plant parameter ") + prefix +
                                    ".edges_per_motor_rev = " +
                                    std::to_string(p.edges_per_motor_rev) +
                                    ": must be even (two edges per magnet)");
    }
}

HallEncoder::HallEncoder(const HallEncoderParams& p, unsigned channel)
    : p_(p),
      channel_(channel),
      spacing_rad_(2.0 * kPi / static_cast<double>(p.edges_per_motor_rev)),
      rng_(p.seed),
      jitter_(0.0, p.jitter_stddev_s > 0.0 ? p.jitter_stddev_s : 1.0),
      missed_(p.missed_edge_probability) {
    reset(0.0);
}

void HallEncoder::reset(double angle_rad) {
    index_ = index_of(angle_rad);
    level_ = true;
    count_ = 0;
    last_edge_s_ = 0.0;
    rng_.seed(p_.seed);
    jitter_.reset();
    missed_.reset();
}

void HallEncoder::set_missed_edge_probability(double p) {
    if (!(p >= 0.0 && p <= 0.5)) {
        throw std::invalid_argument("encoder " + std::to_string(channel_ + 1) + " missed-edge probability " +
                                    std::to_string(p) + ": must be in [0, 0.5]");
    }
    p_.missed_edge_probability = p;
    missed_ = std::bernoulli_distribution(p);
}

std::int64_t HallEncoder::index_of(double angle_rad) const {
    return static_cast<std::int64_t>(std::floor(angle_rad / spacing_rad_ + p_.initial_phase));
}

void HallEncoder::process(const MotorStepper& motor, const MotorSegment& seg, double step_start_s,
                          double step_end_s, EdgeBuffer& out) {
    process([&](double tau) { return motor.state_at(seg, tau); }, seg.t0_s, seg.duration_s,
            seg.start.angle_rad, seg.end.angle_rad, step_start_s, step_end_s, out);
}

void HallEncoder::emit(double t, double step_start_s, double step_end_s, EdgeBuffer& out) {
    if (p_.missed_edge_probability > 0.0 && missed_(rng_)) return;
    if (p_.jitter_stddev_s > 0.0) {
        t += jitter_(rng_);
        t = std::clamp(t, std::max(step_start_s, last_edge_s_), step_end_s);
    }
    last_edge_s_ = t;
    level_ = !level_;
    ++count_;
    out.push(EncoderEdge{channel_, t, level_});
}

}  // namespace ddmr::plant
