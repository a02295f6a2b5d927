#pragma once
// PartSet: the board's `parts:` built and wired, in an order where every part
// is built after the parts whose outputs it reads (the board file may list
// them in any order; a loop is refused when the board file is read,
// part_order()). Each input is resolved to a LogicSignal:
//   a board pin   -> the pin's level as the firmware sets it (PinProbe:
//                    DDR/PORT/PUD; an output's PORT bit, a pulled-up input
//                    high, a floating input low). A timer's compare output
//                    on that pin is not followed: wire a PWM pin to a motor
//                    driver's input instead (MotorDriverReader decodes it).
//   NAME.PORT     -> that part's output;
//   high / low    -> a constant.
// Owns the parts and the signals; destroy before the AvrCore.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/logic_signal.hpp"
#include "hil/parts/part.hpp"
#include "hil/parts/part_registry.hpp"

namespace ddmr::hil {

/// "NAME.PORT" split, or nullopt when `text` names no part output.
struct PartOutputRef {
    std::string part, port;
};
std::optional<PartOutputRef> parse_part_output_ref(const std::string& text);

/// The indices of `entries` in build order (each after the parts it reads).
/// Throws std::invalid_argument "SOURCE:LINE: key 'parts[i].K': ..." for an
/// input naming an unknown part or port, or a loop of parts feeding each other.
std::vector<std::size_t> part_order(const std::vector<PartEntry>& entries, const PartRegistry& registry,
                                    const std::string& source);

class PartSet {
public:
    /// `world` (may be null: the plain floor) must outlive the set.
    PartSet(AvrCore& core, const std::vector<PartEntry>& entries, const PartRegistry& registry,
            const std::function<plant::Pose()>& pose, const plant::World* world = nullptr);
    ~PartSet();
    PartSet(const PartSet&) = delete;
    PartSet& operator=(const PartSet&) = delete;

    [[nodiscard]] bool empty() const { return parts_.empty(); }
    /// Part `name`'s output `port`; throws std::invalid_argument naming them.
    [[nodiscard]] const LogicSignal& output(const std::string& name, const std::string& port) const;
    /// "NAME.PORT" -> output().
    [[nodiscard]] const LogicSignal& signal(const std::string& ref) const;
    /// The part called `name`, or nullptr.
    [[nodiscard]] const Part* find(const std::string& name) const;
    /// Every part's every output port, in build order: (part name, port, signal).
    struct Output {
        std::string part, port;
        const LogicSignal* signal;
    };
    [[nodiscard]] std::vector<Output> outputs() const;
    /// truth.csv's part columns ("NAME.COLUMN") and their values now.
    [[nodiscard]] std::vector<std::string> truth_columns() const;
    /// Each part's warnings, "part 'NAME': ..." (Part::warnings).
    [[nodiscard]] std::vector<std::string> warnings() const;
    void truth_values(std::vector<double>& out) const;
    /// Holds part `name`'s reading `reading` at `value` (nullopt: releases
    /// it), Part::set_reading. Throws std::invalid_argument naming the parts
    /// that have settable readings, the part's readings, or the range.
    void set_reading(const std::string& name, const std::string& reading, std::optional<double> value);
    /// Part::on_plant_step() of every part, in build order (PlantCoupler
    /// calls it after each plant step).
    void on_plant_step(Cycles pose_cycle);

private:
    const LogicSignal& input_signal(const PartEntry& entry, const std::string& key);

    AvrCore& core_;
    std::vector<std::unique_ptr<LogicSignal>> signals_;  ///< pins and constants the parts read
    struct Built {
        std::string name;
        const PartType* type;
        std::unique_ptr<Part> part;
    };
    std::vector<Built> parts_;  ///< in build order
};

}  // namespace ddmr::hil
