#pragma once
// RobotFaults: disturbances a test can apply to the robot while it runs
// (scenario steps `stall`, `battery`, `slip`; issue 7). All off by default;
// the plant is then exactly the fault-free model.
//
//   shaft_locked[m]   motor m's shaft is held (a stalled wheel): its speed is
//                     0 and its angle does not move, so its encoder reports
//                     no edges; the armature current follows
//                     L dI/dt = V - R I (no back-EMF), reaching the stall
//                     current V / R_a. Modelled as stiction without bound:
//                     the shaft stops when the lock is applied and stays in
//                     the motor stepper's stuck regime, solved exactly.
//   source_V          the battery is replaced by an ideal source of this
//                     open-circuit voltage [V] (its internal resistance is
//                     kept; the charge is still counted but no longer lowers
//                     the voltage), as with a bench supply.
//   traction[m]       fraction of wheel m's rolling that moves the robot
//                     [0, 1]: 1 = no slip, 0 = the wheel spins in place. The
//                     motor and its encoder turn as before (the encoder is on
//                     the motor shaft), only the pose sees less motion.

#include <array>
#include <cstddef>
#include <optional>

namespace ddmr::plant {

struct RobotFaults {
    std::array<bool, 2> shaft_locked{};
    std::optional<double> source_V;          ///< [V], (0, 50]
    std::array<double, 2> traction{1.0, 1.0};  ///< [1], [0, 1]
};

/// Throws std::invalid_argument naming the field and value if out of range.
void validate(const RobotFaults& f);

}  // namespace ddmr::plant
