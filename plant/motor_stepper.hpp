#pragma once
// Exact stepping of one DcMotor between input changes.
//
// With the terminal condition and the Coulomb sign held, eqs. (9a), (9b) are
// an affine system  x' = A x + b,  x = (I, w):
//
//       A = [ -R/L_a     -K_a/L_a ]      b = [ V / L_a        ]   R = R_a + R_s
//           [  K_t/J     -F/J     ]          [ -sgn(w) T_c / J ]
//
// solved exactly:  x(t) = x_ss + e^{A t} (x0 - x_ss),   x_ss = -A^{-1} b,
//     integral_0^t x = x_ss t + A^{-1} (e^{A t} - I) (x0 - x_ss),
// which also gives the shaft angle (integral of w) and the charge (integral
// of I). e^{A t} uses the closed form for 2x2 matrices, so any step length,
// from one AVR cycle to seconds, costs the same and has no stepping error.
//
// The piecewise structure is handled by splitting the step at events, each
// solved for its exact time (closed form or bracketed Newton on the exact
// solution):
//   moving   : I, w free.          Events: w reaches 0 (stick or reverse);
//                                  bridge off and I reaches 0.
//   stuck    : w = 0, |K_t I| <= T_c, I first-order.  Event: breakaway
//              (|K_t I| reaches T_c), or I reaches 0 with the bridge off.
//   coasting : bridge off, I = 0, w decays by friction. Event: w reaches 0.
//   stopped  : I = 0, w = 0, bridge off.
// Within one segment w keeps its sign, so the shaft angle is monotonic and
// every encoder boundary is crossed at most once (hall_encoder.hpp).
//
// (state, terminal, h) => (state after h, segments, charge). No heap, no throw.

#include <Eigen/Core>

#include <array>
#include <cstddef>
#include <cstdint>

#include "plant/dc_motor.hpp"

namespace ddmr::plant {

enum class MotorRegime : std::uint8_t { moving, stuck, coasting, stopped };

/// One piece of a step during which one closed-form solution holds.
struct MotorSegment {
    MotorRegime regime = MotorRegime::stopped;
    double t0_s = 0.0;        ///< start, relative to the start of the step [s]
    double duration_s = 0.0;  ///< [s]
    DcMotorState start;       ///< state at t0
    DcMotorState end;         ///< state at t0 + duration
    Eigen::Vector2d x_ss{0.0, 0.0};  ///< moving: -A^{-1} b; stuck: (I_ss, 0); coasting: (0, w_ss)
};

/// Result of advancing one motor over one step.
struct MotorStepResult {
    static constexpr std::size_t kMaxSegments = 12;
    std::array<MotorSegment, kMaxSegments> segments{};
    std::size_t segment_count = 0;
    double charge_C = 0.0;         ///< integral of I_a over the step [C]
    double supply_charge_C = 0.0;  ///< integral of the battery current it caused [C]
};

class MotorStepper {
  public:
    explicit MotorStepper(const DcMotorParams& p);

    /// Advances `x` by `h_s` > 0 with the terminal condition `u` held.
    void advance(DcMotorState& x, const MotorTerminal& u, double h_s, MotorStepResult& out);

    /// The coasting regime (bridge off, I = 0) from `x` for up to `tau_s`:
    /// fills `seg` (not its t0_s) with the exact decay of w by friction. When
    /// w reaches 0 sooner, the segment ends there with w = 0 (the shaft then
    /// stays stopped: Coulomb friction holds it); w = 0 at the start gives a
    /// stopped segment of tau_s.
    void coast(const DcMotorState& x, double tau_s, MotorSegment& seg);

    /// Shaft speed [rad/s] and angle [rad] at `tau_s` into a segment of the
    /// latest advance() (the solution uses the series resistance it had).
    [[nodiscard]] DcMotorState state_at(const MotorSegment& seg, double tau_s) const;

    /// e^{A t} by the closed form for 2x2 matrices.
    [[nodiscard]] Eigen::Matrix2d transition(double t_s) const;

    /// The system matrix A of the moving regime and its eigenvalues
    /// (real parts sorted slow first; imaginary part 0 when real).
    [[nodiscard]] const Eigen::Matrix2d& system_matrix() const { return a_; }
    [[nodiscard]] double slow_eigenvalue_real() const;
    [[nodiscard]] double fast_eigenvalue_real() const;

    [[nodiscard]] const DcMotorParams& params() const { return p_; }

  private:
    struct CacheEntry {
        double h = -1.0;
        Eigen::Matrix2d e = Eigen::Matrix2d::Zero();  ///< e^{A h}
        Eigen::Matrix2d g = Eigen::Matrix2d::Zero();  ///< A^{-1}(e^{A h} - I)
    };
    const CacheEntry& cached(double h);
    /// Coasting decay over h, for the last two step lengths h.
    struct CoastEntry {
        double h = -1.0;
        double decay = 1.0;            ///< e^{-F h / J}
        double one_minus_decay = 0.0;  ///< 1 - e^{-F h / J}, without cancellation
    };
    const CoastEntry& coast_decay(double h);
    /// Rebuilds A and its closed-form data for R = R_a + series_R (when it changes).
    void configure(double series_resistance_ohm);
    /// One segment of advance(): its length (an event may end it early), the
    /// state at its end, the charge that flowed (the integral of I), and
    /// whether the next segment must move (the current broke the friction away).
    struct SegmentOutcome {
        double tau_s;
        DcMotorState end;
        double charge_C;
        bool force_moving;
    };
    struct MovingEvent {
        double t_s;
        int kind;  ///< 0: none, 1: w reaches 0, 2: I reaches 0 (bridge off)
    };
    SegmentOutcome moving_segment(const DcMotorState& x, const MotorTerminal& u, double tau_s, bool last,
                                  MotorSegment& seg);
    [[nodiscard]] MovingEvent moving_event(const MotorSegment& seg, const Eigen::Vector2d& x0,
                                           const Eigen::Vector2d& x1, const Eigen::Vector2d& b, double s,
                                           double tau_s, bool open) const;
    SegmentOutcome stuck_segment(const DcMotorState& x, const MotorTerminal& u, double tau_s, bool last,
                                 MotorSegment& seg) const;
    MotorRegime classify(const DcMotorState& x, const MotorTerminal& u) const;
    double effective_voltage(const DcMotorState& x, const MotorTerminal& u) const;
    double moving_sign(const DcMotorState& x, const MotorTerminal& u) const;

    DcMotorParams p_;
    double coast_time_constant_;  ///< J / F [s]: w's decay while coasting
    double coast_stall_speed_;    ///< T_c / F [rad/s]: |w_ss| while coasting
    double series_ohm_ = -1.0;    ///< R_s the matrices below were built for
    double r_total_ohm_ = 0.0;    ///< R_a + R_s
    Eigen::Matrix2d a_;
    Eigen::Matrix2d a_inv_;
    double half_trace_ = 0.0;     ///< m = tr(A)/2
    double discriminant_ = 0.0;   ///< q = m^2 - det(A): eigenvalues m +- sqrt(q)
    double max_segment_s_ = 0.0;  ///< pi/beta for complex eigenvalues, else infinity
    std::array<CacheEntry, 2> cache_{};
    std::size_t cache_next_ = 0;
    std::array<CoastEntry, 2> coast_cache_{};
    std::size_t coast_next_ = 0;
};

}  // namespace ddmr::plant
