#pragma once
// MotorDriverReader: what each wheel's motor driver does, from the levels
// the firmware puts on the driver's input pins (PinWaveforms) and the
// driver's truth table (plant/motor_driver.hpp).
//
//   board wiring (pin or `high` per driver input)
//   + pin waveforms (timer PWM of every mode, static levels, inputs)
//   => per wheel: the bridge state at any cycle (switched model), the next
//      cycle it may change, and the time-averaged drive (averaged model).
//
// A driver input on a pin the firmware never made an output reads, per the
// driver's datasheet:
//   pull-up on (PORT = 1): high (the AVR's 20-50 kOhm pull-up overrides the
//     TB6612's 200 kOhm and the DRV8833's 150 kOhm / 500 kOhm pull-downs;
//     the L298's TTL input reads it high);
//   floating (PORT = 0): low (TB6612: internal 200 kOhm pull-down, p. 2;
//     DRV8833: internal pull-downs, section 7.3.4; L298: no pull-down is
//     specified and a floating TTL input is undefined: modelled low).
// Each such input is reported by wiring_warnings() (wiring bugs are real).
// An input a part's output drives (`IN1: shield.Q2`) reads that LogicSignal
// (hil/logic_signal.hpp): its level as of the part's last change.
// A wheel with `reversed: true` has its motor leads swapped: the bridge's
// forward turns it backwards.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/board.hpp"
#include "hil/parts/part_set.hpp"
#include "hil/pin_waveforms.hpp"
#include "plant/bridge_driver.hpp"
#include "plant/motor_driver.hpp"

namespace ddmr::hil {

class MotorDriverReader {
public:
    static constexpr Cycles kNever = PinWaveforms::kNever;

    /// `parts` resolves the inputs a part's output drives ("shield.Q2"); it
    /// must outlive the reader (nullptr: the board has no such input).
    MotorDriverReader(AvrCore& core, const BoardWiring& board, const PartSet* parts = nullptr);

    /// Applies buffered timer updates due by `cycle` (non-decreasing); call
    /// before reading the drive at that cycle.
    void advance_to(Cycles cycle) { pins_.advance_to(cycle); }

    /// Wheel m's bridge input as of the last advance_to: the averaged drive
    /// (duty = net fraction of the period driven, forward = its direction as
    /// the wheel turns, brake fraction) and the state during `cycle`.
    [[nodiscard]] plant::BridgeInput input_at(std::size_t m, Cycles cycle) const;
    /// The bridge state of wheel m during `cycle`.
    [[nodiscard]] plant::BridgeState state_at(std::size_t m, Cycles cycle) const;
    /// First cycle after `cycle` at which an input of wheel m's driver may change level, or kNever.
    [[nodiscard]] Cycles next_change_after(std::size_t m, Cycles cycle) const;
    /// What the driver reads on input `r` of wheel m during `cycle`.
    [[nodiscard]] bool input_level(std::size_t m, DriverRole r, Cycles cycle) const;

    /// One line per wired driver input the firmware never made an output
    /// (call at the end of a run): "pin 12 (right L298N EN) is never set as
    /// an output: the driver sees only the pull-up"; and one per input whose
    /// timer the firmware took over (PinWaveforms::takeover): "pin 9 (left
    /// L298N EN) is OC1A of Timer1, which the firmware ran in normal mode
    /// (WGM 0) from 0.0012 s: analogWrite(9) makes no PWM there ...".
    [[nodiscard]] std::vector<std::string> wiring_warnings() const;

    [[nodiscard]] const BoardWiring& board() const { return board_; }
    [[nodiscard]] PinWaveforms& pins() { return pins_; }
    [[nodiscard]] const PinWaveforms& pins() const { return pins_; }
    /// Register accesses that changed a driver input so far.
    [[nodiscard]] uint64_t changes() const { return pins_.changes(); }
    std::optional<Cycles> take_first_change() { return pins_.take_first_change(); }

private:
    struct Input {
        DriverRole role;
        bool tied_high;
        int pin;
        const LogicSignal* signal;  ///< a part's output drives it (else a pin or high)
        bool plant::DriverInputLevels::*level;   ///< the truth table's field for this input
        double plant::DriverInputDuties::*duty;  ///< the averaged model's field
    };
    struct Wheel {
        plant::DriverType driver;
        bool reversed;
        std::array<Input, kDriverRoleCount> inputs;  ///< the first `count` are used
        std::size_t count = 0;
    };
    [[nodiscard]] bool level_of(const Input& in, Cycles cycle) const;
    [[nodiscard]] std::string takeover_warning(std::size_t m, const Input& in, const PinWaveforms::Takeover& t) const;
    [[nodiscard]] double duty_of(const Input& in) const;

    /// The averaged drive of a wheel as of a PinWaveforms revision: it
    /// changes only with a register, not with the cycle.
    struct AveragedCache {
        uint64_t revision = ~uint64_t{0};
        plant::BridgeInput input{};
    };
    [[nodiscard]] plant::BridgeInput averaged(std::size_t m) const;
    /// Changes whenever an input of wheel m may have changed (pins and parts' outputs).
    [[nodiscard]] uint64_t revision(std::size_t m) const;

    BoardWiring board_;
    PinWaveforms pins_;
    double core_clock_hz_;
    std::array<Wheel, 2> wheel_{};
    mutable std::array<AveragedCache, 2> averaged_{};
};

}  // namespace ddmr::hil
