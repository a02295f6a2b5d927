#include "plant/battery.hpp"

#include <algorithm>

namespace ddmr::plant {

const std::array<Field<BatteryParams>, 4>& battery_fields() {
    using P = BatteryParams;
    static const std::array<Field<P>, 4> table{{
        {"open_circuit_V", "V", positive(50.0), &P::open_circuit_V},
        {"capacity_Ah", "Ah", positive(100.0), &P::capacity_Ah},
        {"internal_resistance_ohm", "ohm", non_negative(10.0), &P::internal_resistance_ohm},
        {"sag_V_per_Ah", "V/Ah", non_negative(10.0), &P::sag_V_per_Ah},
    }};
    return table;
}

void validate(const BatteryParams& p, const char* prefix) {
    validate_fields(p, battery_fields(), prefix);
}

double source_voltage_V(const BatteryParams& p, const BatteryState& s) {
    const double drawn_Ah = s.charge_drawn_C / kSecondsPerHour;
    return p.open_circuit_V - p.sag_V_per_Ah * drawn_Ah;
}

double terminal_voltage_V(const BatteryParams& p, const BatteryState& s, double supply_current_A) {
    const double v = source_voltage_V(p, s) - p.internal_resistance_ohm * supply_current_A;
    return std::max(v, 0.0);
}

double state_of_charge(const BatteryParams& p, const BatteryState& s) {
    return 1.0 - s.charge_drawn_C / kSecondsPerHour / p.capacity_Ah;
}

}  // namespace ddmr::plant
