#include "lockstep.hpp"

#include <utility>

namespace ddmr::tools {

void Lockstep::compare(const hil::MachineState& a, const hil::MachineState& b, bool a_ended, bool b_ended) {
    hil::StateComparison c = hil::compare_machine_states(a, b, mcu_, objects_);
    // Both ended at the same cycle in the same state: equal. One ended, the
    // other at a checkpoint: a difference even in the same state (one goes on).
    if (c.equal() && a_ended == b_ended) {
        ++equal_;
        last_equal_ = a.cycle;
        return;
    }
    if (c.equal()) {
        c.total = 1;
        c.shown.push_back(hil::StateDifference{"the run", a_ended ? "ended" : "goes on", b_ended ? "ended" : "goes on"});
    }
    divergence_ = LockstepDivergence{last_equal_, a, b, a_ended, b_ended, std::move(c)};
}

void Lockstep::compare_sides(Side side, const hil::MachineState& mine, bool mine_ended,
                             const hil::MachineState& theirs, bool theirs_ended) {
    if (side == kA) {
        compare(mine, theirs, mine_ended, theirs_ended);
    } else {
        compare(theirs, mine, theirs_ended, mine_ended);
    }
}

void Lockstep::checkpoint(Side side, hil::MachineState s) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (divergence_) return;
    const Side o = other(side);
    if (pending_[o]) {
        compare_sides(side, s, false, *pending_[o], false);
        pending_[o].reset();
        cv_.notify_all();
        return;
    }
    if (ended_[o]) {
        if (final_[o]) compare_sides(side, s, false, *final_[o], true);
        return;
    }
    pending_[side] = std::move(s);
    cv_.wait(lock, [&] { return !pending_[side] || ended_[o] || divergence_; });
    if (pending_[side] && ended_[o] && !divergence_ && final_[o]) {
        compare_sides(side, *pending_[side], false, *final_[o], true);
    }
    pending_[side].reset();
}

void Lockstep::ended(Side side, std::optional<hil::MachineState> s) {
    std::lock_guard<std::mutex> lock(mutex_);
    ended_[side] = true;
    final_[side] = std::move(s);
    const Side o = other(side);
    if (!divergence_ && final_[side]) {
        const hil::MachineState& mine = *final_[side];
        if (pending_[o]) {
            compare_sides(side, mine, true, *pending_[o], false);
            pending_[o].reset();
        } else if (ended_[o] && final_[o]) {
            compare_sides(side, mine, true, *final_[o], true);
        }
    }
    cv_.notify_all();
}

uint64_t Lockstep::checkpoints_equal() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return equal_;
}

hil::Cycles Lockstep::last_equal_cycle() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return last_equal_;
}

std::optional<LockstepDivergence> Lockstep::divergence() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return divergence_;
}

}  // namespace ddmr::tools
