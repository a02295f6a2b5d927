// 74HC595: 8-bit serial-in, parallel-out shift register with output latches
// (the Adafruit Motor Shield v1's direction bits; SENSORS.md section 8).
//
// Nexperia 74HC595 / 74HCT595 datasheet (rev. 8):
//   section 1 and section 7 Table 3 (function table):
//     SHCP LOW-to-HIGH: the shift register shifts; DS enters stage 0, stage 7
//       appears on Q7S;
//     STCP LOW-to-HIGH: the shift register's contents go to the storage register;
//     OE LOW: Q0..Q7 follow the storage register; OE HIGH: Q0..Q7 are
//       high-impedance (Q7S is not gated);
//     MR LOW: clears the shift register only (not the storage register).
//   Table 7 (74HC at 4.5 V): tsu DS->SHCP 10 ns, th 3 ns, tpd STCP->Qn 20 ns
//     typ: far below one 16 MHz cycle (62.5 ns) and the microseconds between
//     the digitalWrite()s that drive it, so this model is edge-ideal: DS is
//     sampled at the SHCP edge's cycle and Qn change at the STCP edge's cycle.
// A high-impedance output reads as low to the part it feeds (no pull-up is
// specified on the L293D's inputs; like a floating L298 input,
// hil/motor_driver_reader.hpp).

#include "hil/parts/builtin_parts.hpp"

#include <fmt/format.h>

#include <array>
#include <memory>
#include <stdexcept>

namespace ddmr::hil {
namespace {

class ShiftRegister595 final : public Part {
public:
    explicit ShiftRegister595(const PartContext& ctx)
        : ds_(ctx.input("DS")), oe_(ctx.input("OE")), mr_(ctx.input("MR")), q7s_(ctx.name() + ".Q7S") {
        for (std::size_t i = 0; i < q_.size(); ++i) {
            q_[i] = std::make_unique<DrivenSignal>(fmt::format("{}.Q{}", ctx.name(), i));
        }
        ctx.input("SHCP").add_listener([this](bool level, Cycles cycle) {
            if (level) shift(cycle);
        });
        ctx.input("STCP").add_listener([this](bool level, Cycles cycle) {
            if (level) latch(cycle);
        });
        oe_.add_listener([this](bool, Cycles cycle) { drive(cycle); });
        mr_.add_listener([this](bool level, Cycles cycle) {
            if (!level) clear(cycle);
        });
    }

    const LogicSignal& output(const std::string& port) const override {
        if (port == "Q7S") return q7s_;
        for (std::size_t i = 0; i < q_.size(); ++i) {
            if (port == fmt::format("Q{}", i)) return *q_[i];
        }
        throw std::logic_error("74hc595: no port " + port);
    }
    std::vector<std::string> truth_columns() const override { return {"Q"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(outputs()); }

private:
    /// Q0..Q7 as a byte (0 while OE is high).
    [[nodiscard]] uint8_t outputs() const {
        uint8_t b = 0;
        for (std::size_t i = 0; i < q_.size(); ++i) b = static_cast<uint8_t>(b | (q_[i]->level() << i));
        return b;
    }
    void shift(Cycles cycle) {
        if (!mr_.level_at(cycle)) return;  // held cleared
        shift_ = static_cast<uint8_t>((shift_ << 1) | (ds_.level_at(cycle) ? 1 : 0));
        q7s_.set((shift_ & 0x80) != 0, cycle);
    }
    void latch(Cycles cycle) {
        storage_ = shift_;
        drive(cycle);
    }
    void clear(Cycles cycle) {
        shift_ = 0;
        q7s_.set(false, cycle);
    }
    void drive(Cycles cycle) {
        const bool enabled = !oe_.level_at(cycle);
        for (std::size_t i = 0; i < q_.size(); ++i) q_[i]->set(enabled && ((storage_ >> i) & 1U) != 0, cycle);
    }

    const LogicSignal& ds_;
    const LogicSignal& oe_;
    const LogicSignal& mr_;
    std::array<std::unique_ptr<DrivenSignal>, 8> q_;
    DrivenSignal q7s_;
    uint8_t shift_ = 0;    ///< stages 0..7 (power-on content is undefined: 0 here)
    uint8_t storage_ = 0;  ///< the storage register
};

}  // namespace

PartType shift_register_74hc595_type() {
    PartType t;
    t.type = "74hc595";
    t.summary = "8-bit shift register with output latches (Adafruit Motor Shield v1 direction bits)";
    t.datasheet = "Nexperia 74HC595/74HCT595 rev. 8, section 7 Table 3 (function table), Table 7 (timing)";
    t.keys = {
        PartKey::input("DS", "serial data in, sampled at SHCP's rising edge (AFMotor MOTORDATA: D8)"),
        PartKey::input("SHCP", "shift clock: on LOW-to-HIGH, DS enters stage 0 (AFMotor MOTORCLK: D4)"),
        PartKey::input("STCP", "storage clock: on LOW-to-HIGH, the stages go to Q0..Q7 (AFMotor MOTORLATCH: D12)"),
        PartKey::input_or("OE", "output enable, active low: high makes Q0..Q7 high-impedance (AFMotor MOTORENABLE: D7)",
                          "low"),
        PartKey::input_or("MR", "master reset, active low: clears the stages, not the outputs", "high"),
    };
    for (int i = 0; i < 8; ++i) {
        t.ports.push_back({fmt::format("Q{}", i), fmt::format("output {}: stage {} as latched (low while OE is high)", i, i)});
    }
    t.ports.push_back({"Q7S", "serial out: stage 7, for a second 74HC595's DS"});
    t.create = [](const PartContext& ctx) { return std::make_unique<ShiftRegister595>(ctx); };
    return t;
}

}  // namespace ddmr::hil
