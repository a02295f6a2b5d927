// Tests for plant/hall_encoder: 8 edges per motor revolution (4 magnets,
// both edges), exact edge times, no direction output, seeded jitter/misses.
#include "plant/hall_encoder.hpp"

#include <gtest/gtest.h>

#include "support/motor_terminals.hpp"

#include <cmath>
#include <vector>

#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

using test::driven;

struct EncoderRun {
    std::vector<EncoderEdge> edges;
    DcMotorState final_state;
};

/// Drives one motor at `volts` for `seconds` in steps of `h`, collecting edges.
EncoderRun run(const HallEncoderParams& ep, double volts, double seconds, double h) {
    const DcMotorParams mp;
    MotorStepper motor(mp);
    HallEncoder enc(ep, 0);
    DcMotorState x;
    MotorStepResult r;
    EdgeBuffer buf;
    EncoderRun out;
    const auto n = static_cast<int>(std::lround(seconds / h));
    for (int k = 0; k < n; ++k) {
        const double t0 = k * h;
        motor.advance(x, driven(volts), h, r);
        buf.clear();
        for (std::size_t s = 0; s < r.segment_count; ++s) enc.process(motor, r.segments[s], t0, t0 + h, buf);
        out.edges.insert(out.edges.end(), buf.begin(), buf.end());
    }
    out.final_state = x;
    EXPECT_EQ(enc.edge_count(), out.edges.size());
    return out;
}

TEST(HallEncoder, CountsEightEdgesPerMotorRevolutionExactly) {
    const EncoderRun r = run(HallEncoderParams{}, 4.7, 1.0, 1e-4);
    // Boundaries sit at (k - 0.5) * 2 pi / 8 (initial_phase 0.5), so after a
    // shaft angle theta the count is floor(8 theta / 2 pi + 0.5): 8 per revolution.
    const double revs = r.final_state.angle_rad / (2.0 * kPi);
    EXPECT_EQ(r.edges.size(), static_cast<std::size_t>(std::floor(8.0 * revs + 0.5)));
    // ~1 s at up to 1057 rad/s ~ 160 revolutions: a count in the thousands.
    EXPECT_GT(r.edges.size(), 1000u);
}

TEST(HallEncoder, EdgeTimesAreMonotonicAndExact) {
    const EncoderRun r = run(HallEncoderParams{}, 4.7, 0.2, 1e-4);
    ASSERT_GT(r.edges.size(), 50u);
    bool level = true;
    for (std::size_t k = 0; k < r.edges.size(); ++k) {
        if (k > 0) {
            EXPECT_GT(r.edges[k].t_s, r.edges[k - 1].t_s);
        }
        level = !level;
        EXPECT_EQ(r.edges[k].level, level);  // toggles at every edge
    }
    // Re-solve the motor exactly up to a few edge times: the shaft angle there
    // is on boundary k: (k + 1 - 0.5) * pi / 4.
    const DcMotorParams mp;
    for (std::size_t k : {std::size_t{0}, std::size_t{10}, r.edges.size() - 1}) {
        MotorStepper m(mp);
        DcMotorState x;
        MotorStepResult res;
        m.advance(x, driven(4.7), r.edges[k].t_s, res);
        EXPECT_NEAR(x.angle_rad, (static_cast<double>(k) + 0.5) * kPi / 4.0, 1e-9) << k;
    }
}

TEST(HallEncoder, NoDirectionOutputReverseAlsoCounts) {
    const EncoderRun fwd = run(HallEncoderParams{}, 4.7, 0.3, 1e-4);
    const EncoderRun rev = run(HallEncoderParams{}, -4.7, 0.3, 1e-4);
    // Mirror-image motion crosses the same number of boundaries.
    EXPECT_EQ(fwd.edges.size(), rev.edges.size());
    EXPECT_LT(rev.final_state.angle_rad, 0.0);
}

TEST(HallEncoder, StepLengthDoesNotMoveTheEdges) {
    const EncoderRun a = run(HallEncoderParams{}, 4.7, 0.1, 1e-3);
    const EncoderRun b = run(HallEncoderParams{}, 4.7, 0.1, 1e-5);
    ASSERT_EQ(a.edges.size(), b.edges.size());
    for (std::size_t k = 0; k < a.edges.size(); ++k) EXPECT_NEAR(a.edges[k].t_s, b.edges[k].t_s, 1e-12);
}

TEST(HallEncoder, JitterAndMissedEdgesAreSeededAndOffByDefault) {
    const EncoderRun exact = run(HallEncoderParams{}, 4.7, 0.5, 1e-4);
    HallEncoderParams noisy;
    noisy.jitter_stddev_s = 20e-6;
    noisy.missed_edge_probability = 0.1;
    noisy.seed = 42;
    const EncoderRun a = run(noisy, 4.7, 0.5, 1e-4);
    const EncoderRun b = run(noisy, 4.7, 0.5, 1e-4);
    ASSERT_EQ(a.edges.size(), b.edges.size());  // same seed: same bytes
    for (std::size_t k = 0; k < a.edges.size(); ++k) EXPECT_EQ(a.edges[k].t_s, b.edges[k].t_s);
    // ~10 % lost: n = exact count, kept ~ 0.9 n +- 3 sqrt(0.09 n).
    const double n = static_cast<double>(exact.edges.size());
    EXPECT_NEAR(static_cast<double>(a.edges.size()), 0.9 * n, 3.0 * std::sqrt(0.09 * n));
    for (std::size_t k = 1; k < a.edges.size(); ++k) EXPECT_GE(a.edges[k].t_s, a.edges[k - 1].t_s);
    noisy.seed = 43;
    const EncoderRun c = run(noisy, 4.7, 0.5, 1e-4);
    // Another seed: another draw (the 6th edge time or the count differs).
    const bool same = a.edges.size() == c.edges.size() && a.edges[5].t_s == c.edges[5].t_s;
    EXPECT_FALSE(same);
}

TEST(HallEncoder, RejectsAnOddEdgeCount) {
    HallEncoderParams p;
    p.edges_per_motor_rev = 7;
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::plant
