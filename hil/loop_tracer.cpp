#include "hil/loop_tracer.hpp"

namespace ddmr::hil {

LoopTracer::LoopTracer(const FirmwareVariables& vars, const TracedVariable& marker,
                       const std::vector<TracedVariable>& variables)
    : vars_(vars), marker_(vars.lookup(marker.name, marker.type)), names_(variables) {
    for (const auto& v : variables) variables_.push_back(vars_.lookup(v.name, v.type));
    values_.resize(variables_.size());
}

void LoopTracer::poll(Cycles cycle) {
    const double m = vars_.read(marker_);
    if (!primed_) {
        primed_ = true;
        last_marker_ = m;
        return;
    }
    // Bitwise-exact comparisons on purpose: any store to the marker counts.
    const auto same = [](double a, double b) { return a == b || (a != a && b != b); };
    if (same(m, last_marker_)) {
        has_candidate_ = false;
        return;
    }
    if (!has_candidate_ || !same(m, candidate_)) {
        has_candidate_ = true;  // new value: confirm it at the next poll
        candidate_ = m;
        candidate_cycle_ = cycle;
        return;
    }
    has_candidate_ = false;
    last_marker_ = m;
    ++iterations_;
    for (std::size_t i = 0; i < variables_.size(); ++i) values_[i] = vars_.read(variables_[i]);
    if (sink_) sink_(candidate_cycle_, values_);
}

}  // namespace ddmr::hil
