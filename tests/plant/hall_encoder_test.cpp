// Tests for plant/hall_encoder: 8 edges per motor revolution (4 magnets,
// both edges), exact edge times, no direction output, seeded jitter/misses;
// quadrature A/B and a resolution given per wheel revolution.
#include "plant/hall_encoder.hpp"

#include <gtest/gtest.h>

#include "support/motor_terminals.hpp"

#include <array>
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
    HallEncoder enc(ep, 0, mp.gear_ratio);
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

HallEncoderParams quadrature() {
    HallEncoderParams p;
    p.channels = 2;
    return p;
}

/// (A, B) as the sub-index j mod 4 of hall_encoder.hpp: 00 -> 0, 10 -> 1, 11 -> 2, 01 -> 3.
int quadrature_phase(bool a, bool b) {
    if (a) return b ? 2 : 1;
    return b ? 3 : 0;
}

/// Replays the edges on levels that start at (a, b); returns the phase
/// change at each edge (+1 or -1 mod 4), failing on any other change.
std::vector<int> phase_steps(const std::vector<EncoderEdge>& edges, bool a, bool b) {
    std::vector<int> steps;
    for (const EncoderEdge& e : edges) {
        const int before = quadrature_phase(a, b);
        (e.signal == 0 ? a : b) = e.level;
        const int d = (quadrature_phase(a, b) - before + 4) % 4;
        EXPECT_TRUE(d == 1 || d == 3) << "edge at " << e.t_s << " changed both or neither";
        steps.push_back(d == 1 ? 1 : -1);
    }
    return steps;
}

TEST(HallEncoder, QuadratureForwardALeadsBAndReverseBLeadsA) {
    // At angle 0, j = floor(0 / (spacing / 2) + 2 x 0.5) = 1: (A, B) = (1, 0).
    const HallEncoder at_rest(quadrature(), 0, 48.0);
    EXPECT_TRUE(at_rest.level(0));
    EXPECT_FALSE(at_rest.level(1));
    // Forward the code steps 10 -> 11 -> 01 -> 00 -> 10 (A changes, then B a
    // quarter period later): +1 at every edge. Reverse: -1 at every edge.
    const EncoderRun fwd = run(quadrature(), 4.7, 0.1, 1e-4);
    const EncoderRun rev = run(quadrature(), -4.7, 0.1, 1e-4);
    ASSERT_GT(fwd.edges.size(), 100u);
    for (int d : phase_steps(fwd.edges, true, false)) EXPECT_EQ(d, 1);
    for (int d : phase_steps(rev.edges, true, false)) EXPECT_EQ(d, -1);
    // Forward, the first edge is B's rise (j 1 -> 2), then A falls (2 -> 3).
    EXPECT_EQ(fwd.edges[0].signal, 1u);
    EXPECT_TRUE(fwd.edges[0].level);
    EXPECT_EQ(fwd.edges[1].signal, 0u);
    EXPECT_FALSE(fwd.edges[1].level);
    // Reverse, A falls first (j 1 -> 0), then B rises (0 -> -1 = 3 mod 4).
    EXPECT_EQ(rev.edges[0].signal, 0u);
    EXPECT_EQ(rev.edges[1].signal, 1u);
    EXPECT_TRUE(rev.edges[1].level);
}

TEST(HallEncoder, QuadratureHasFourEdgesPerAPeriodAndTwiceTheCount) {
    const EncoderRun r = run(quadrature(), 4.7, 1.0, 1e-4);
    // A and B alternate: between two rises of A lie exactly 4 edges (4x).
    std::vector<std::size_t> a_rises;
    for (std::size_t k = 0; k < r.edges.size(); ++k) {
        if (k > 0) {
            EXPECT_NE(r.edges[k].signal, r.edges[k - 1].signal) << k;
        }
        if (r.edges[k].signal == 0 && r.edges[k].level) a_rises.push_back(k);
    }
    ASSERT_GT(a_rises.size(), 100u);
    for (std::size_t k = 1; k < a_rises.size(); ++k) EXPECT_EQ(a_rises[k] - a_rises[k - 1], 4u);
    // Sub-boundaries every 2 pi / 16 from j = 1 at angle 0: after theta the
    // count is floor(16 theta / 2 pi + 1) - 1, i.e. 2 x 8 per motor revolution.
    const double revs = r.final_state.angle_rad / (2.0 * kPi);
    EXPECT_EQ(r.edges.size(), static_cast<std::size_t>(std::floor(16.0 * revs + 1.0) - 1.0));
    // Each output alone still changes 8 times per revolution.
    std::size_t a_edges = 0;
    for (const EncoderEdge& e : r.edges) a_edges += e.signal == 0 ? 1 : 0;
    EXPECT_NEAR(static_cast<double>(a_edges), 8.0 * revs, 1.0);
}

TEST(HallEncoder, QuadratureEdgeTimesAreExactOnBothOutputs) {
    // Edge k (from j = 1) lies on sub-boundary k + 2, at angle
    // (k + 2 - 2 x 0.5) x (2 pi / 8) / 2 = (k + 1) pi / 8, A's and B's alike.
    const EncoderRun r = run(quadrature(), 4.7, 0.05, 1e-4);
    ASSERT_GT(r.edges.size(), 20u);
    const DcMotorParams mp;
    for (std::size_t k : {std::size_t{0}, std::size_t{1}, std::size_t{10}, std::size_t{11}}) {
        MotorStepper m(mp);
        DcMotorState x;
        MotorStepResult res;
        m.advance(x, driven(4.7), r.edges[k].t_s, res);
        EXPECT_NEAR(x.angle_rad, (static_cast<double>(k) + 1.0) * kPi / 8.0, 1e-9) << k;
    }
}

TEST(HallEncoder, QuadratureMissedEdgeLeavesThatOutputsLevel) {
    HallEncoderParams p = quadrature();
    p.missed_edge_probability = 0.2;
    p.seed = 7;
    const EncoderRun r = run(p, 4.7, 0.3, 1e-4);
    // Each output toggles on its own reported edges only.
    std::array<bool, 2> level{true, false};
    for (const EncoderEdge& e : r.edges) {
        level[e.signal] = !level[e.signal];
        EXPECT_EQ(e.level, level[e.signal]);
    }
    const EncoderRun exact = run(quadrature(), 4.7, 0.3, 1e-4);
    EXPECT_LT(r.edges.size(), exact.edges.size());
}

TEST(HallEncoder, EdgesPerWheelRevolutionSetTheSpacingThroughTheGear) {
    // A 20-slot disc on the wheel: 40 edges of OUT per wheel turn; with the
    // 48:1 gear the boundaries are 2 pi x 48 / 40 = 7.54 rad apart at the motor.
    HallEncoderParams p;
    p.edges_per_motor_rev = 0;
    p.edges_per_wheel_rev = 40.0;
    EXPECT_NO_THROW(validate(p, "encoder1"));
    EXPECT_DOUBLE_EQ(boundary_spacing_rad(p, 48.0), 2.0 * kPi * 48.0 / 40.0);
    const EncoderRun r = run(p, 4.7, 1.0, 1e-4);
    const double wheel_revs = r.final_state.angle_rad / (2.0 * kPi * 48.0);
    ASSERT_GT(wheel_revs, 3.0);  // ~160 motor turns in 1 s
    EXPECT_EQ(r.edges.size(), static_cast<std::size_t>(std::floor(40.0 * wheel_revs + 0.5)));
}

TEST(HallEncoder, ExactlyOneResolutionAndOneOrTwoChannels) {
    HallEncoderParams p;
    p.edges_per_wheel_rev = 40.0;  // and edges_per_motor_rev = 8: both
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
    p.edges_per_motor_rev = 0;
    p.edges_per_wheel_rev = 0.0;  // neither
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
    p.edges_per_wheel_rev = 41.0;  // odd
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
    p.edges_per_wheel_rev = 40.5;  // not whole
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
    p.edges_per_wheel_rev = 40.0;
    EXPECT_NO_THROW(validate(p, "encoder1"));
    p.channels = 3;
    EXPECT_THROW(validate(p, "encoder1"), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::plant
