#include "plant/drive_stepper.hpp"

#include <algorithm>

namespace ddmr::plant {

DriveStepResult step_across_edges(Robot& robot, RobotInput& input, const DriveWaveforms& waves,
                                  std::int64_t from, std::int64_t to, std::uint32_t clock_hz,
                                  EdgeBuffer& edges, const PieceSink& sink) {
    DriveStepResult result;
    const bool switched = input.mode == DriveMode::switched;
    std::int64_t t = from;
    while (t < to) {
        std::int64_t next = to;
        if (switched) {
            for (std::size_t m = 0; m < kMotorCount; ++m) {
                input.bridge[m].state = waves.state_at(m, t);
                next = std::min(next, waves.next_change_after(m, t));
            }
        }
        robot.set_input(input);
        edges.clear();
        const StepResult r =
            robot.step(static_cast<double>(next - t) / static_cast<double>(clock_hz), edges);
        ++result.pieces;
        if (sink) sink(t, edges);
        result.status = r.status;
        result.t_s = r.t_s;
        if (r.status != StepStatus::ok) return result;
        t = next;
    }
    return result;
}

}  // namespace ddmr::plant
