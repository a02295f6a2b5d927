#pragma once
// The robot plant: two DC gear motors, each behind one bridge of a motor
// driver, the battery, two encoders and the differential-drive kinematics,
// composed. It never sees pins: the HIL turns the input levels into bridge
// states with the driver's truth table (motor_driver.hpp) and hands them over.
//
//   RobotInput (mode, per bridge: state, or duty, direction and brake fraction)
//     -> bridge (battery voltage)    => MotorTerminal x2           (bridge_driver.hpp)
//     -> MotorStepper x2 (exact)     => I, w, shaft angle, charge  (motor_stepper.hpp)
//     -> HallEncoder x2              => EncoderEdge (exact times)  (hall_encoder.hpp)
//     -> Battery                     => charge drawn, V_batt       (battery.hpp)
//     -> kinematics, exact arc       => pose x, y, theta           (diff_drive_kinematics.hpp)
//
// Index 0 = motor 1 = RIGHT wheel; index 1 = motor 2 = LEFT. Each bridge has
// its chip's parameters (bridge_params(params, m)); the thesis robot's are
// the L298's.
//
// step(dt) holds the input constant over dt and splits it into equal internal
// steps of at most params.stepper.max_step_s. It never allocates and never
// throws: problems come back as a StepStatus; a non-finite state stops the
// run (status diverged, sticky). The battery's internal resistance R_b
// couples the motors (eq. 19); how each internal step is solved:
//   switched : both motors together, exactly (coupled_motors.hpp), while both
//              shafts turn; a regime change (a speed reaching zero, a diode
//              current reaching zero: discontinuous conduction) ends that
//              solution at its exact time. With both bridges off and both
//              currents at zero (the off-time of a PWM period once the
//              diodes stop conducting) nothing couples the motors: each shaft
//              coasts on its own exact solution (MotorStepper::coast). While
//              one motor is stuck or open-circuit, motor by motor
//              (motor_stepper.hpp, exact for each), over pieces of at most
//              params.stepper.event_step_s with the other motor's battery
//              current held at its mean over the piece (predictor-corrector;
//              exact when one motor draws nothing).
//   averaged : motor by motor with the held coupling over the whole step:
//              the supply currents are continuous there, so this is second
//              order and as accurate (docs/plant.md), without one
//              eigendecomposition per duty value.
// The source voltage V_0 - k AH is held at its start-of-step value in the
// joint solution (it moves by ~1e-8 V per step) and at its midpoint value
// in the motor-by-motor one.

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "plant/battery.hpp"
#include "plant/body_contact.hpp"
#include "plant/bridge_driver.hpp"
#include "plant/coupled_motors.hpp"
#include "plant/dc_motor.hpp"
#include "plant/diff_drive_kinematics.hpp"
#include "plant/encoder_edge.hpp"
#include "plant/hall_encoder.hpp"
#include "plant/motor_stepper.hpp"
#include "plant/robot_faults.hpp"
#include "plant/robot_params.hpp"

namespace ddmr::plant {

inline constexpr std::size_t kMotorCount = 2;

struct RobotInput {
    DriveMode mode = DriveMode::averaged;
    std::array<BridgeInput, kMotorCount> bridge{};  ///< [0]: motor 1 (right), [1]: motor 2 (left)
};

/// Everything the stepper advances.
struct RobotState {
    double t_s = 0.0;                                   ///< plant time [s]
    std::array<DcMotorState, kMotorCount> motor{};
    BatteryState battery{};
    Pose pose{};
    /// cos and sin of the heading as carried from step to step
    /// (diff_drive_kinematics.hpp): part of the state, so a restored state
    /// continues bit for bit as the original run did.
    HeadingTrig heading{};
};

enum class StepStatus {
    ok,
    bad_input,      ///< dt not in (0, 10] s, a duty or brake fraction not in [0, 1] / NaN,
                    ///< or an unknown bridge state: nothing advanced
    diverged,       ///< a state became non-finite; the run is stopped (see diverged_at_s)
    edge_overflow,  ///< the EdgeBuffer filled up; EdgeBuffer::dropped() edges were lost
};

const char* to_string(StepStatus s);

/// The body meeting a wall (body_contact.hpp).
struct ContactEvent {
    double t_s = 0.0;        ///< plant time of the step that would have entered the wall
    double x_m = 0.0, y_m = 0.0;  ///< the contact point
    double speed_m_s = 0.0;  ///< the robot's forward speed then (magnitude)
    std::size_t wall = 0;    ///< index in World::walls
};

struct StepResult {
    StepStatus status = StepStatus::ok;
    double t_s = 0.0;  ///< plant time after the step (or where it stopped)
};

class Robot {
  public:
    /// Validates `params`; throws std::invalid_argument naming the parameter.
    explicit Robot(const RobotParams& params = default_robot_params());

    /// Time 0, motors at rest, battery full, counters 0, at `pose`.
    void reset(const Pose& pose = {});

    void set_input(const RobotInput& input) { input_ = input; }
    [[nodiscard]] const RobotInput& input() const { return input_; }

    /// Advances by dt_s with the current input held; appends the encoder
    /// edges of the step to `edges`, sorted by time.
    StepResult step(double dt_s, EdgeBuffer& edges);

    // --- outputs ---------------------------------------------------------
    [[nodiscard]] double time_s() const { return state_.t_s; }
    [[nodiscard]] const Pose& pose() const { return state_.pose; }
    [[nodiscard]] BodyVelocity body_velocity() const;
    [[nodiscard]] double motor_current_A(std::size_t m) const { return state_.motor[m].current_A; }
    [[nodiscard]] double motor_speed_rad_s(std::size_t m) const { return state_.motor[m].speed_rad_s; }
    [[nodiscard]] double motor_angle_rad(std::size_t m) const { return state_.motor[m].angle_rad; }
    [[nodiscard]] double wheel_speed_rad_s(std::size_t m) const;
    /// Battery current of both bridges now [A] (eq. 19's I_1 + I_2).
    [[nodiscard]] double supply_current_A() const;
    /// Battery terminal voltage now, eq. (19) [V].
    [[nodiscard]] double battery_voltage_V() const;
    [[nodiscard]] double charge_drawn_C() const { return state_.battery.charge_drawn_C; }
    /// Edges of encoder m so far, of all its outputs.
    [[nodiscard]] std::uint64_t edge_count(std::size_t m) const { return encoder_[m].edge_count(); }
    /// The level output `signal` of encoder m has now (0: OUT or A, 1: B);
    /// the HIL drives the pins to these levels at start-up.
    [[nodiscard]] bool encoder_level(std::size_t m, unsigned signal = 0) const {
        return encoder_[m].level(signal);
    }

    [[nodiscard]] StepStatus status() const { return status_; }
    [[nodiscard]] double diverged_at_s() const { return diverged_at_s_; }
    [[nodiscard]] const RobotState& state() const { return state_; }
    // --- faults (robot_faults.hpp) ----------------------------------------
    /// Applies `faults` from now on (validated; throws std::invalid_argument).
    void set_faults(const RobotFaults& faults);
    [[nodiscard]] const RobotFaults& faults() const { return faults_; }
    /// Moves the robot by (dx, dy) in the inertial frame and turns it by
    /// dtheta, as a push would; wheels and encoders are untouched.
    void displace(const Pose& delta);
    /// Probability that encoder m misses an edge from now on, [0, 0.5]
    /// (throws std::invalid_argument); drawn from the encoder's seeded generator.
    void set_missed_edge_probability(std::size_t m, double p);
    /// Overwrites the state (snapshots, tests). Does not move the encoders.
    void set_state(const RobotState& s) { state_ = s; }
    [[nodiscard]] const RobotParams& params() const { return params_; }
    [[nodiscard]] const MotorStepper& motor_stepper(std::size_t m) const { return stepper_[m]; }

    // --- the world's walls (body_contact.hpp) ------------------------------
    /// The walls the body cannot pass through from now on (null: none); must
    /// outlive the robot or be replaced first.
    void set_world(const World* world);
    /// Whether the body rests against a wall now.
    [[nodiscard]] bool in_contact() const { return contact_.has_value(); }
    /// Contacts begun so far; the first kContactLog of them in contacts().
    [[nodiscard]] std::uint64_t contact_count() const { return contact_count_; }
    [[nodiscard]] const std::vector<ContactEvent>& contacts() const { return contact_log_; }
    static constexpr std::size_t kContactLog = 64;

  private:
    static RobotParams validated(const RobotParams& p);
    /// A held shaft: a stall fault, or the wheels stalled against a wall.
    [[nodiscard]] bool held(std::size_t m) const { return faults_.shaft_locked[m] || contact_held_[m]; }
    /// After a step with walls: undoes a move into a wall and holds or frees
    /// the wheels (body_contact.hpp). `before` is the state the step began in.
    void resolve_contact(const RobotState& before);
    [[nodiscard]] bool input_valid() const;
    [[nodiscard]] double supply_current_A(std::size_t m) const;
    /// Both motors in one exact joint solution over up to h: returns the time
    /// advanced (h, or up to a regime change), 0 when refused (a motor stuck
    /// or open-circuit), -1 when the state diverged.
    double joint_substep(double h, EdgeBuffer& edges);
    /// Switched mode: bridge m coasts and motor m's current is zero, so it
    /// stays zero (open circuit, no supply current) for the rest of the step.
    [[nodiscard]] bool open_circuit(std::size_t m) const;
    /// Switched mode with both bridges coasting and no current in either motor:
    /// both shafts coast (or stand), uncoupled, each exactly.
    [[nodiscard]] bool both_coasting() const;
    bool coast_substep(double h, EdgeBuffer& edges);
    /// Motor by motor, each exact, with the battery coupling held over h.
    bool substep(double h, EdgeBuffer& edges);
    /// Switched mode: whether neither motor is open-circuit or braking, i.e.
    /// both may draw battery current during the step (otherwise holding the
    /// idle motor's zero supply current in the other motor's solution is exact).
    [[nodiscard]] bool battery_coupled() const;
    /// Pose, time and the finiteness check at the end of an internal step.
    bool finish_substep(const RobotState& before, double h);

    RobotParams params_;
    std::array<MotorStepper, kMotorCount> stepper_;
    std::array<MotorStepper, kMotorCount> held_;  ///< the same motors with the shaft held (faults)
    std::array<HallEncoder, kMotorCount> encoder_;
    RobotInput input_{};
    RobotState state_{};
    RobotFaults faults_{};
    StepStatus status_ = StepStatus::ok;
    double diverged_at_s_ = 0.0;
    std::array<MotorStepResult, kMotorCount> scratch_{};
    CoupledMotorStepper coupled_;
    CoupledSegment joint_{};
    const World* world_ = nullptr;
    std::optional<WallContact> contact_;     ///< the wall the body rests against
    std::array<bool, kMotorCount> contact_held_{};  ///< stalled against it
    std::uint64_t contact_count_ = 0;
    std::vector<ContactEvent> contact_log_;  ///< reserved by set_world: step() does not allocate
};

}  // namespace ddmr::plant
