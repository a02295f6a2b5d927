#include "scenario/fault_steps.hpp"

#include <algorithm>

#include "plant/units.hpp"
#include "plant/world.hpp"

namespace ddmr::tools::scenario {

void FaultSteps::set_faults(const std::function<void(plant::RobotFaults&)>& change) {
    plant::RobotFaults f = rig_.robot().faults();
    change(f);
    rig_.robot().set_faults(f);
}

std::string FaultSteps::run(const InjectDrop& d) {
    const auto m = static_cast<std::size_t>(d.encoder - 1);
    rig_.robot().set_missed_edge_probability(m, d.drop);
    if (d.duration) session_.at(now() + *d.duration, [this, m] { rig_.robot().set_missed_edge_probability(m, 0.0); });
    return {};
}

std::string FaultSteps::run(const Stall& st) {
    const auto m = static_cast<std::size_t>(st.motor - 1);
    set_faults([m](plant::RobotFaults& f) { f.shaft_locked[m] = true; });
    session_.at(now() + st.duration, [this, m] { set_faults([m](plant::RobotFaults& f) { f.shaft_locked[m] = false; }); });
    return {};
}

std::string FaultSteps::run(const Battery& b) {
    set_faults([&](plant::RobotFaults& f) { f.source_V = b.volts; });
    if (b.duration) {
        session_.at(now() + *b.duration, [this] { set_faults([](plant::RobotFaults& f) { f.source_V.reset(); }); });
    }
    return {};
}

std::string FaultSteps::run(const Slip& sl) {
    const auto m = static_cast<std::size_t>(sl.wheel - 1);
    set_faults([&](plant::RobotFaults& f) { f.traction[m] = sl.traction; });
    if (sl.duration) {
        session_.at(now() + *sl.duration, [this, m] { set_faults([m](plant::RobotFaults& f) { f.traction[m] = 1.0; }); });
    }
    return {};
}

std::string FaultSteps::run(const Place& p) {
    const plant::Pose at = rig_.robot().pose();
    rig_.robot().displace({p.x_m - at.x_m, p.y_m - at.y_m, p.heading_deg * plant::kPi / 180.0 - at.theta_rad});
    return {};
}

std::string FaultSteps::run(const Push& p) {
    spread(p.over, [this, p](double f) { rig_.robot().displace(plant::Pose{p.dx_m * f, p.dy_m * f, p.dtheta_rad * f}); });
    return {};
}

std::string FaultSteps::run(const MoveObstacle& m) {
    plant::World& world = rig_.world();
    const std::size_t index = *plant::find_obstacle(world, m.name);  // checked when the scenario was read
    spread(m.over, [&world, index, m](double f) { plant::move_obstacle(world, index, Eigen::Vector2d(m.dx_m * f, m.dy_m * f)); });
    return {};
}

void FaultSteps::spread(hil::Cycles over, const std::function<void(double)>& apply) {
    if (over == 0) {
        apply(1.0);
        return;
    }
    const hil::Cycles start = now();
    spread_from(apply, start, start + over, start);
}

void FaultSteps::spread_from(const std::function<void(double)>& apply, hil::Cycles start, hil::Cycles end,
                             hil::Cycles done) {
    const hil::Cycles next = std::min(end, done + rig_.coupler().config().step_cycles);
    session_.at(next, [this, apply, start, end, done, next] {
        apply(static_cast<double>(next - done) / static_cast<double>(end - start));
        if (next < end) spread_from(apply, start, end, next);
    });
}

}  // namespace ddmr::tools::scenario
