// The scenario model's own functions (scenario.hpp): comparison operators,
// and what a scenario needs of the run.
#include "scenario/scenario.hpp"

#include <algorithm>

namespace ddmr::tools::scenario {

const char* to_string(CompareOp op) {
    switch (op) {
        case CompareOp::kEq: return "==";
        case CompareOp::kNe: return "!=";
        case CompareOp::kLt: return "<";
        case CompareOp::kLe: return "<=";
        case CompareOp::kGt: return ">";
        case CompareOp::kGe: return ">=";
    }
    return "?";
}

bool holds(double lhs, CompareOp op, double rhs) {
    switch (op) {
        case CompareOp::kEq: return lhs == rhs;
        case CompareOp::kNe: return lhs != rhs;
        case CompareOp::kLt: return lhs < rhs;
        case CompareOp::kLe: return lhs <= rhs;
        case CompareOp::kGt: return lhs > rhs;
        case CompareOp::kGe: return lhs >= rhs;
    }
    return false;
}

bool Scenario::needs_loop_profile() const {
    return std::any_of(steps.begin(), steps.end(),
                       [](const Step& s) { return std::holds_alternative<ExpectLoop>(s.action); });
}

}  // namespace ddmr::tools::scenario
