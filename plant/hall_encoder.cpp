#include "plant/hall_encoder.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ddmr::plant {

const std::array<Field<HallEncoderParams>, 6>& hall_encoder_fields() {
    using P = HallEncoderParams;
    static const std::array<Field<P>, 6> table{{
        {"edges_per_motor_rev", "1", Range{0.0, 4096.0, true, true}, &P::edges_per_motor_rev},
        {"edges_per_wheel_rev", "1", non_negative(1e6), &P::edges_per_wheel_rev},
        {"initial_phase", "1", Range{0.0, 1.0, true, false}, &P::initial_phase},
        {"jitter_stddev_s", "s", non_negative(1e-3), &P::jitter_stddev_s},
        {"missed_edge_probability", "1", non_negative(0.5), &P::missed_edge_probability},
        {"seed", "1", Range{}, &P::seed},
    }};
    return table;
}

namespace {
std::string number_text(double v) {
    std::ostringstream os;
    os.precision(17);
    os << v;
    return os.str();
}
}  // namespace

void validate(const HallEncoderParams& p, const char* prefix) {
    validate_fields(p, hall_encoder_fields(), prefix);
    const std::string name = std::string("invalid plant parameter ") + prefix + ".";
    if (p.edges_per_motor_rev % 2 != 0) {
        throw std::invalid_argument(name + "edges_per_motor_rev = " +
                                    std::to_string(p.edges_per_motor_rev) +
                                    ": must be even (two edges per magnet)");
    }
    if (std::fmod(p.edges_per_wheel_rev, 2.0) != 0.0) {
        throw std::invalid_argument(name + "edges_per_wheel_rev = " +
                                    number_text(p.edges_per_wheel_rev) +
                                    ": must be an even whole number (two edges per slot or magnet)");
    }
    // 0 means "not given": exactly one of the two resolutions must be.
    if ((p.edges_per_motor_rev > 0) == (p.edges_per_wheel_rev > 0.0)) {
        throw std::invalid_argument(name + "edges_per_motor_rev = " +
                                    std::to_string(p.edges_per_motor_rev) + " and " + prefix +
                                    ".edges_per_wheel_rev = " + number_text(p.edges_per_wheel_rev) +
                                    ": give exactly one of them (> 0), the other 0");
    }
    if (p.channels != 1 && p.channels != 2) {
        throw std::invalid_argument(name + "channels = " + std::to_string(p.channels) +
                                    ": must be 1 (single output) or 2 (quadrature A, B)");
    }
}

double boundary_spacing_rad(const HallEncoderParams& p, double gear_ratio) {
    if (p.edges_per_motor_rev > 0) return 2.0 * kPi / static_cast<double>(p.edges_per_motor_rev);
    return 2.0 * kPi * gear_ratio / p.edges_per_wheel_rev;
}

HallEncoder::HallEncoder(const HallEncoderParams& p, unsigned channel, double gear_ratio)
    : p_(p),
      channel_(channel),
      spacing_rad_(boundary_spacing_rad(p, gear_ratio)),
      index_step_rad_(p.channels == 2 ? 0.5 * spacing_rad_ : spacing_rad_),
      index_offset_(p.channels == 2 ? 2.0 * p.initial_phase : p.initial_phase),
      rng_(p.seed),
      jitter_(0.0, p.jitter_stddev_s > 0.0 ? p.jitter_stddev_s : 1.0),
      missed_(p.missed_edge_probability) {
    reset(0.0);
}

void HallEncoder::reset(double angle_rad) {
    index_ = index_of(angle_rad);
    if (p_.channels == 2) {
        // (A, B) = j mod 4 -> 0: (0, 0), 1: (1, 0), 2: (1, 1), 3: (0, 1).
        const std::int64_t phase = ((index_ % 4) + 4) % 4;
        level_ = {phase == 1 || phase == 2, phase == 2 || phase == 3};
    } else {
        level_ = {true, false};
    }
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
    return static_cast<std::int64_t>(std::floor(angle_rad / index_step_rad_ + index_offset_));
}

unsigned HallEncoder::signal_of(std::int64_t boundary) const {
    if (p_.channels != 2) return 0;
    // Odd boundaries (j: 0 -> 1, 2 -> 3) change A, even ones B.
    return boundary % 2 != 0 ? 0U : 1U;
}

void HallEncoder::process(const MotorStepper& motor, const MotorSegment& seg, double step_start_s,
                          double step_end_s, EdgeBuffer& out) {
    process([&](double tau) { return motor.state_at(seg, tau); }, seg.t0_s, seg.duration_s,
            seg.start.angle_rad, seg.end.angle_rad, step_start_s, step_end_s, out);
}

void HallEncoder::emit(unsigned signal, double t, double step_start_s, double step_end_s,
                       EdgeBuffer& out) {
    if (p_.missed_edge_probability > 0.0 && missed_(rng_)) return;
    if (p_.jitter_stddev_s > 0.0) {
        t += jitter_(rng_);
        t = std::clamp(t, std::max(step_start_s, last_edge_s_), step_end_s);
    }
    last_edge_s_ = t;
    level_[signal] = !level_[signal];
    ++count_;
    EncoderEdge e;
    e.channel = channel_;
    e.t_s = t;
    e.level = level_[signal];
    e.signal = signal;
    out.push(e);
}

}  // namespace ddmr::plant
