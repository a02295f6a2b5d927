#pragma once
// step_across_edges: the one place the plant is stepped across the edges of
// its drive (issue 32: the HIL coupler, the host simulation and the `plant`
// command all step through it).
//
// In averaged mode the robot is stepped once over [from, to) with the input
// as given (the bridges' mean drive). In switched mode the interval is split
// at every level change of the drive waveforms, and each piece is stepped
// with the bridge states the waveforms give at its start, so each PWM edge
// falls on a plant step boundary at its exact cycle.
//
// Time is counted in cycles of the MCU's clock (`clock_hz`); plant time is
// AVR time (both start at reset).

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>

#include "plant/bridge_state.hpp"
#include "plant/encoder_edge.hpp"
#include "plant/pwm_waveform.hpp"
#include "plant/robot.hpp"

namespace ddmr::plant {

/// The bridges' switching waveforms: per motor a bridge state that changes
/// only at cycles the waveform can tell in advance.
class DriveWaveforms {
public:
    static constexpr std::int64_t kNever = std::numeric_limits<std::int64_t>::max();
    virtual ~DriveWaveforms() = default;
    /// Motor m's bridge state during `cycle`.
    [[nodiscard]] virtual BridgeState state_at(std::size_t m, std::int64_t cycle) const = 0;
    /// The first cycle after `cycle` at which motor m's state may change; kNever if it never does.
    [[nodiscard]] virtual std::int64_t next_change_after(std::size_t m, std::int64_t cycle) const = 0;
};

/// The host's idealised drive: each bridge's enable is the Uno's
/// phase-correct analogWrite waveform, its direction held (forward or
/// reverse while the enable is high, coast while it is low).
class PwmDrive final : public DriveWaveforms {
public:
    std::array<PhaseCorrectPwm, kMotorCount> pwm{};
    std::array<bool, kMotorCount> forward{};
    [[nodiscard]] BridgeState state_at(std::size_t m, std::int64_t cycle) const override {
        if (!pwm[m].level_at(cycle)) return BridgeState::coast;
        return forward[m] ? BridgeState::forward : BridgeState::reverse;
    }
    [[nodiscard]] std::int64_t next_change_after(std::size_t m, std::int64_t cycle) const override {
        return pwm[m].next_edge_after(cycle);
    }
};

struct DriveStepResult {
    StepStatus status = StepStatus::ok;
    double t_s = 0.0;          ///< plant time where the status stopped being ok (else the end)
    std::uint64_t pieces = 0;  ///< Robot::step calls made (1 in averaged mode)
};

/// Called after each piece with its first cycle and the encoder edges the
/// piece produced (the buffer is cleared before every piece).
using PieceSink = std::function<void(std::int64_t piece_start, const EdgeBuffer& edges)>;

/// Steps `robot` over [from, to) (from < to) with `input` held; in switched
/// mode `input.bridge[m].state` is set from `waves` for each piece. Stops
/// after the first piece whose status is not ok (that piece's edges are
/// still handed to `sink`).
DriveStepResult step_across_edges(Robot& robot, RobotInput& input, const DriveWaveforms& waves,
                                  std::int64_t from, std::int64_t to, std::uint32_t clock_hz,
                                  EdgeBuffer& edges, const PieceSink& sink = {});

}  // namespace ddmr::plant
