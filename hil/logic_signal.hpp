#pragma once
// LogicSignal: a digital signal one part reads from another: a part's output
// port ("shield.Q2", the 74HC595's third output) as a motor driver's input,
// or a board pin as a part's input. It tells the level at a cycle, its
// time-averaged high fraction (the averaged plant model), the next cycle it
// is known to change, and calls listeners at each change (edge-triggered
// parts such as a shift register's clock).
//
// Levels are known up to "now" (the AVR's cycle): a part's output that
// follows a firmware write changes at that write's cycle, and reads as its
// present level for every later cycle until then (next_change_after:
// kNever). A signal with a scheduled future (a decoded timer waveform) says
// so through next_change_after.

#include <cstdint>
#include <functional>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "hil/avr_core.hpp"

namespace ddmr::hil {

class LogicSignal {
public:
    static constexpr Cycles kNever = std::numeric_limits<Cycles>::max();
    /// (new level, cycle of the change). Runs inside the firmware's register
    /// write: keep it short, do not throw.
    using Listener = std::function<void(bool, Cycles)>;

    LogicSignal() = default;
    virtual ~LogicSignal() = default;
    LogicSignal(const LogicSignal&) = delete;
    LogicSignal& operator=(const LogicSignal&) = delete;

    /// The level during `cycle` (>= the last change told).
    [[nodiscard]] virtual bool level_at(Cycles cycle) const = 0;
    /// The time-averaged fraction of time high, as of now, in [0, 1].
    [[nodiscard]] virtual double duty() const = 0;
    /// The first cycle after `cycle` at which the level is known to change, or kNever.
    [[nodiscard]] virtual Cycles next_change_after(Cycles /*cycle*/) const { return kNever; }
    /// Changes whenever level_at() or duty() may have changed (a counter).
    [[nodiscard]] uint64_t revision() const { return revision_; }
    /// What the messages call it: "pin 8", "shield.Q2".
    [[nodiscard]] const std::string& label() const { return label_; }

    /// `listener` is called at each change from now on (listening does not
    /// change the signal); the id removes it (a listener that dies first must).
    using ListenerId = uint64_t;
    ListenerId add_listener(Listener listener) const {
        listeners_.emplace_back(++last_id_, std::move(listener));
        return last_id_;
    }
    void remove_listener(ListenerId id) const {
        for (auto it = listeners_.begin(); it != listeners_.end(); ++it) {
            if (it->first == id) {
                listeners_.erase(it);
                return;
            }
        }
    }

protected:
    explicit LogicSignal(std::string label) : label_(std::move(label)) {}
    /// Counts a change and tells the listeners.
    void changed(bool level, Cycles cycle) {
        ++revision_;
        for (const auto& [id, listener] : listeners_) listener(level, cycle);
    }

private:
    std::string label_;
    uint64_t revision_ = 0;
    mutable std::vector<std::pair<ListenerId, Listener>> listeners_;
    mutable ListenerId last_id_ = 0;
};

/// A signal a part sets: its level changes when the part says so.
class DrivenSignal final : public LogicSignal {
public:
    explicit DrivenSignal(std::string label, bool level = false) : LogicSignal(std::move(label)), level_(level) {}
    [[nodiscard]] bool level_at(Cycles /*cycle*/) const override { return level_; }
    [[nodiscard]] double duty() const override { return level_ ? 1.0 : 0.0; }
    [[nodiscard]] bool level() const { return level_; }
    /// Sets the level at `cycle` (a no-op when unchanged).
    void set(bool level, Cycles cycle) {
        if (level == level_) return;
        level_ = level;
        changed(level, cycle);
    }

private:
    bool level_;
};

}  // namespace ddmr::hil
