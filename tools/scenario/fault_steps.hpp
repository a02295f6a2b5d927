#pragma once
// The scenario steps that act on the robot and its world rather than check
// something (docs/scenarios.md, "Faults"): inject, stall, battery, slip,
// place, push, move-obstacle. Each changes the plant now, and a timed one
// (`for`, `over`) schedules the rest on the session's clock: nothing blocks,
// the next step starts at once.
#include <functional>
#include <string>

#include "hil/session.hpp"
#include "scenario/scenario.hpp"

namespace ddmr::tools::scenario {

class FaultSteps {
public:
    explicit FaultSteps(hil::Session& session) : session_(session), rig_(session.rig()) {}

    std::string run(const InjectDrop& d);
    std::string run(const Stall& st);
    std::string run(const Battery& b);
    std::string run(const Slip& sl);
    std::string run(const Place& p);
    std::string run(const Push& p);
    std::string run(const MoveObstacle& m);

private:
    void set_faults(const std::function<void(plant::RobotFaults&)>& change);
    /// Applies a change at once (over = 0: apply(1)), or evenly over `over`
    /// cycles: apply(fraction) at each coupling step, the fractions summing
    /// to 1 (a hand's even turn that a gyro feels, an obstacle sliding).
    void spread(hil::Cycles over, const std::function<void(double)>& apply);
    void spread_from(const std::function<void(double)>& apply, hil::Cycles start, hil::Cycles end, hil::Cycles done);
    [[nodiscard]] hil::Cycles now() const { return rig_.core().cycle(); }

    hil::Session& session_;
    hil::RobotRig& rig_;
};

}  // namespace ddmr::tools::scenario
