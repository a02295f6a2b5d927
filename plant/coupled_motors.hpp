#pragma once
// Exact joint solution of both motors while they share the battery.
//
// The pack's internal resistance R_b couples the bridges (eq. 19): each motor
// sees V_b = V_s - R_b (s_1 I_1 + s_2 I_2), where V_s = V_0 - k AH is the
// source voltage and s_m the supply factor of bridge m (duty x direction in
// the averaged model, +-1 while driving, 0 while braking, -sgn(I_m) while its
// current returns through the flyback diodes). With E_m the terminal voltage bridge m would
// give at zero supply current (V_s - drop, or V_s + 2 V_f through the diodes)
// and R_s,m the bridge's own switches in series (on-resistance while driving,
// brake resistance while braking, bridge_driver.hpp), eqs. (9a), (9b) of both
// motors become one affine system in x = (I_1, w_1, I_2, w_2):
//
//   L_m dI_m/dt = s_m E_m - (R_a,m + R_s,m) I_m - K_a,m w_m - s_m R_b (s_1 I_1 + s_2 I_2)
//   J_m dw_m/dt = K_t,m I_m - F_m w_m - sgn(w_m) T_c,m
//
// i.e. x' = A x + b with a 4x4 A (two motor blocks plus the rank-one battery
// coupling). While both shafts turn (no stiction, no current reaching zero
// through the diodes) it is solved exactly:
//   x(t) = x_ss + e^{A t} (x0 - x_ss),              x_ss = -A^{-1} b
//   integral_0^t x = x_ss t + A^{-1} (e^{A t} - I) (x0 - x_ss)
// with e^{A t} = V e^{Lambda t} V^{-1} from A's eigendecomposition, which is
// computed once per coupling (s_1, s_2, R_b, R_s,1, R_s,2) and cached: in switched mode
// there are a handful of them, in averaged mode one per duty change.
//
// A regime change (a shaft reaching zero speed, where it sticks or reverses;
// a diode current reaching zero, after which that motor is open-circuit) ends
// the joint segment at its exact time. advance() refuses to start while a
// motor is stuck or open-circuit; the caller (Robot) then solves the step
// motor by motor (motor_stepper.hpp, every regime and event), which is exact
// when one motor draws no current and otherwise holds the coupling over
// short pieces. No heap, no throw.

#include <Eigen/Core>

#include <array>
#include <complex>
#include <cstddef>
#include <utility>

#include "plant/dc_motor.hpp"

namespace ddmr::plant {

/// What one bridge imposes, in the coupled form: terminal voltage
/// supply_factor * (emf_V - R_b * supply current of both bridges)
/// - series_resistance_ohm * I.
struct CoupledTerminal {
    double supply_factor = 0.0;  ///< s_m: battery current per motor ampere [1]
    double emf_V = 0.0;          ///< E_m: the terminal voltage / s_m at zero supply current [V]
    bool diode = false;          ///< bridge off: the current flows through the diodes and must keep its sign
    /// R_s,m: the bridge's own switches in series with the armature (on- or
    /// brake resistance) [ohm], >= 0. Not the R_b share: A has that already.
    double series_resistance_ohm = 0.0;
};

/// Converts a MotorTerminal built for a battery of zero internal resistance
/// (bridge_driver.hpp's terminal() with battery_resistance_ohm = 0, so its
/// series resistance is the bridge's own) and the motor's current into the
/// coupled form. For an open bridge the supply factor is -sgn(I): the diode
/// current flows back into the pack. Inline: it runs twice per plant step.
inline CoupledTerminal coupled_terminal(const MotorTerminal& u, double current_A) {
    CoupledTerminal c;
    c.series_resistance_ohm = u.series_resistance_ohm;
    if (u.kind == MotorTerminal::Kind::driven) {
        c.supply_factor = u.supply_factor;
        // voltage_V = s E; with s = 0 the terminal is shorted (E irrelevant).
        c.emf_V = u.supply_factor != 0.0 ? u.voltage_V / u.supply_factor : 0.0;
    } else {
        // Through the diodes the terminal is -sgn(I)(V_b + 2 V_f) and the
        // battery takes back |I|: s = -sgn(I), E = clamp.
        c.supply_factor = current_A > 0.0 ? -1.0 : (current_A < 0.0 ? 1.0 : 0.0);
        c.emf_V = u.clamp_V;
        c.diode = true;
    }
    return c;
}

/// One joint step: both motors' exact trajectory over [0, duration_s].
struct CoupledSegment {
    double duration_s = 0.0;
    std::array<DcMotorState, 2> start{};
    Eigen::Vector4d x_ss = Eigen::Vector4d::Zero();  ///< -A^{-1} b
    Eigen::Vector4d d0 = Eigen::Vector4d::Zero();    ///< x0 - x_ss
    std::size_t config = 0;  ///< which cached decomposition
    // Modal form, computed on first use (edge times, events), not per step:
    mutable bool modes_ready = false;
    mutable Eigen::Vector4cd modes = Eigen::Vector4cd::Zero();  ///< V^{-1} d0
    /// V diag(modes): x(t) = x_ss + sum_j coef(:, j) e^{lambda_j t}
    mutable Eigen::Matrix4cd coef = Eigen::Matrix4cd::Zero();
};

class CoupledMotorStepper {
  public:
    CoupledMotorStepper(const DcMotorParams& motor1, const DcMotorParams& motor2);

    /// Advances both motors by up to `h_s` > 0 with the terminals held and
    /// the battery's internal resistance `battery_resistance_ohm` coupling
    /// them, and returns the time advanced: `h_s`, or the time of the first
    /// regime change inside the step (a speed or a diode current reaching
    /// zero, found on the exact solution; that component is then exactly 0).
    /// Returns 0 and leaves `x` untouched when a motor is not turning at the
    /// start, a motor's bridge is off with no current, or A's
    /// eigendecomposition is ill-conditioned. `supply_charge_C` is the
    /// integral of the battery current (s_1 I_1 + s_2 I_2) over the time advanced [C].
    double advance(std::array<DcMotorState, 2>& x, const std::array<CoupledTerminal, 2>& u,
                   double battery_resistance_ohm, double h_s, CoupledSegment& seg,
                   double& supply_charge_C);

    /// Motor m's state `tau_s` into a segment of the latest advance().
    [[nodiscard]] DcMotorState state_at(const CoupledSegment& seg, std::size_t m,
                                        double tau_s) const;

    /// The system matrix A for supply factors s1, s2, R_b and the bridges'
    /// series resistances r1, r2 (for tests).
    [[nodiscard]] Eigen::Matrix4d system_matrix(double s1, double s2, double rb_ohm,
                                                double r1_ohm = 0.0, double r2_ohm = 0.0) const;

  private:
    void resolve_modes(const CoupledSegment& seg) const;
    /// Whether component k (a speed) keeps the sign `s` over [0, h] by
    /// Taylor's bound s x_k(t) >= s x_k(0) + s x_k'(0) t - M t^2 / 2, where
    /// M = sum_j |coef(k, j)| |lambda_j|^2 e^{max(Re lambda_j, 0) h} bounds |x_k''|.
    [[nodiscard]] bool keeps_sign(const CoupledSegment& seg, Eigen::Index k, double s, double x0,
                                  double dx0, double h) const;
    /// Component k of x (order 0) or x' (order 1) at tau, with its time derivative.
    [[nodiscard]] std::pair<double, double> component_at(const CoupledSegment& seg, Eigen::Index k,
                                                         int order, double tau_s) const;

    struct Config {
        double s1 = 0.0, s2 = 0.0, rb = -1.0;  ///< key; rb < 0: unused slot
        double r1 = 0.0, r2 = 0.0;             ///< key: the bridges' series resistances [ohm]
        bool usable = false;                   ///< eigendecomposition well conditioned
        bool real_modes = false;               ///< all eigenvalues real (the usual case)
        double max_imag = 0.0;                 ///< largest |Im lambda| [1/s]
        Eigen::Matrix4d a = Eigen::Matrix4d::Zero();
        Eigen::Matrix4d a_inv = Eigen::Matrix4d::Zero();
        Eigen::Vector4cd lambda = Eigen::Vector4cd::Zero();
        Eigen::Matrix4cd v = Eigen::Matrix4cd::Zero();
        Eigen::Matrix4cd v_inv = Eigen::Matrix4cd::Zero();
        Eigen::Matrix4d v_real = Eigen::Matrix4d::Zero();      ///< V when real_modes
        Eigen::Matrix4d v_inv_real = Eigen::Matrix4d::Zero();  ///< V^{-1} when real_modes
        // e^{A h} and A^{-1}(e^{A h} - I) for the last two step lengths.
        std::array<double, 2> h{-1.0, -1.0};
        std::array<Eigen::Matrix4d, 2> e{};
        std::array<Eigen::Matrix4d, 2> g{};
        std::size_t next_h = 0;
    };
    std::size_t config_for(const std::array<CoupledTerminal, 2>& u, double rb);
    void build(Config& c) const;
    std::size_t transition_for(Config& c, double h);
    /// e^{lambda_j tau} for each mode.
    static Eigen::Vector4cd exp_modes(const Config& c, double tau_s);

    std::array<DcMotorParams, 2> p_;
    static constexpr std::size_t kConfigs = 8;
    std::array<Config, kConfigs> configs_{};
    std::size_t next_config_ = 0;
    std::size_t last_config_ = 0;  ///< checked first: the coupling rarely changes
};

}  // namespace ddmr::plant
