#pragma once
// Lockstep: two runs of one firmware, each on its own thread, meet at the
// same checkpoints (every 10 ms of AVR time, and at their ends) and compare
// their machine states (hil/machine_state.hpp). The first checkpoint at
// which they differ is kept, with the last at which they were equal; from
// then on neither waits for the other, so each runs to its own end. Used by
// the fast-forward verification (tools/fast_forward_verify.hpp): run A with
// fast-forward, run B without.
//
// A run that ends (or fails) while the other is still at checkpoints is a
// difference too: the state it ended with against the other's. Thread-safe.

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>

#include "hil/machine_state.hpp"

namespace ddmr::hil {
class DataObjects;
struct McuDescription;
}  // namespace ddmr::hil

namespace ddmr::tools {

/// The first checkpoint at which two runs differ.
struct LockstepDivergence {
    hil::Cycles last_equal_cycle = 0;  ///< the last checkpoint at which they were equal (0: reset)
    hil::MachineState a, b;            ///< the states at the checkpoint that differs
    bool a_ended = false, b_ended = false;  ///< that state was the run's end
    hil::StateComparison comparison;
};

class Lockstep {
public:
    enum Side { kA = 0, kB = 1 };
    Lockstep(const hil::McuDescription& mcu, const hil::DataObjects* objects) : mcu_(mcu), objects_(objects) {}

    /// `side` reached a checkpoint in state `s`: waits for the other side's
    /// (or its end), unless they already differ.
    void checkpoint(Side side, hil::MachineState s);
    /// `side`'s run ended in state `s` (or was abandoned: nullopt, after an
    /// error); the other side no longer waits for it.
    void ended(Side side, std::optional<hil::MachineState> s);

    [[nodiscard]] uint64_t checkpoints_equal() const;
    [[nodiscard]] hil::Cycles last_equal_cycle() const;
    [[nodiscard]] std::optional<LockstepDivergence> divergence() const;

private:
    void compare(const hil::MachineState& a, const hil::MachineState& b, bool a_ended, bool b_ended);
    void compare_sides(Side side, const hil::MachineState& mine, bool mine_ended, const hil::MachineState& theirs,
                       bool theirs_ended);
    static Side other(Side s) { return s == kA ? kB : kA; }

    const hil::McuDescription& mcu_;
    const hil::DataObjects* objects_;
    mutable std::mutex mutex_;
    std::condition_variable cv_;
    std::optional<hil::MachineState> pending_[2];  ///< a checkpoint waiting for the other side
    bool ended_[2] = {false, false};
    std::optional<hil::MachineState> final_[2];
    uint64_t equal_ = 0;
    hil::Cycles last_equal_ = 0;
    std::optional<LockstepDivergence> divergence_;
};

}  // namespace ddmr::tools
