#pragma once
// LoopTracer: one sample of chosen firmware globals per control-loop
// iteration, with nothing added to the firmware. An iteration is recognised
// by a change of a marker variable (the reference sketch's float `t`, which
// advances by dt just before delay(9)), polled at each plant-coupling
// boundary. A poll can fall between the byte stores of a multi-byte marker
// (a torn read), so a new value counts only when the next poll reads it
// again: the sample is taken one to two coupling steps after the change,
// stamped with the cycle of the first poll that saw the new value.
//
// (AVR data memory at a boundary) => (cycle, values in `variables` order)

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "hil/cycle_time.hpp"
#include "hil/firmware_variables.hpp"

namespace ddmr::hil {

struct TracedVariable {
    std::string name;
    VarType type = VarType::kFloat;
};

class LoopTracer {
public:
    /// Looks every variable up (throws naming a missing or mis-sized one).
    LoopTracer(const FirmwareVariables& vars, const TracedVariable& marker,
               const std::vector<TracedVariable>& variables);

    /// Called with each iteration's sample (inside the simulation).
    void set_sink(std::function<void(Cycles, const std::vector<double>&)> sink) { sink_ = std::move(sink); }

    /// Polls the marker; call at each coupling boundary.
    void poll(Cycles cycle);

    uint64_t iterations() const { return iterations_; }
    const std::vector<TracedVariable>& variables() const { return names_; }

private:
    const FirmwareVariables& vars_;
    Variable marker_;
    std::vector<Variable> variables_;
    std::vector<TracedVariable> names_;
    std::vector<double> values_;
    double last_marker_ = 0.0;
    bool primed_ = false;
    bool has_candidate_ = false;
    double candidate_ = 0.0;
    Cycles candidate_cycle_ = 0;
    uint64_t iterations_ = 0;
    std::function<void(Cycles, const std::vector<double>&)> sink_;
};

}  // namespace ddmr::hil
