#include "plant/l298_driver.hpp"

#include <algorithm>

namespace ddmr::plant {

const std::array<Field<L298Params>, 2>& l298_fields() {
    using P = L298Params;
    static const std::array<Field<P>, 2> table{{
        {"drop_V", "V", non_negative(5.0), &P::drop_V},
        {"flyback_diode_drop_V", "V", non_negative(3.0), &P::flyback_diode_drop_V},
    }};
    return table;
}

void validate(const L298Params& p, const char* prefix) { validate_fields(p, l298_fields(), prefix); }

MotorTerminal terminal(const L298Params& p, DriveMode mode, const BridgeInput& in,
                       double source_V, double battery_resistance_ohm) {
    // Terminal voltage f (V_b - drop) with V_b = source - R_b f I:
    //   = f (source - drop) - f^2 R_b I, f = supply factor.
    // Bridge off: -sgn(I)(V_b + 2 V_f) with V_b = source + R_b |I|:
    //   = -sgn(I)(source + 2 V_f) - R_b I.
    MotorTerminal t;
    const double sign = in.forward ? 1.0 : -1.0;
    // The bridge cannot reverse the supply: below the drop it passes nothing.
    const double available_V = std::max(source_V - p.drop_V, 0.0);
    if (mode == DriveMode::averaged) {
        t.kind = MotorTerminal::Kind::driven;
        t.voltage_V = sign * in.duty * available_V;
        // Chopper average: the battery supplies the motor current duty of the time.
        t.supply_factor = sign * in.duty;
        t.series_resistance_ohm = in.duty * in.duty * battery_resistance_ohm;
    } else if (in.enable) {
        t.kind = MotorTerminal::Kind::driven;
        t.voltage_V = sign * available_V;
        t.supply_factor = sign;
        t.series_resistance_ohm = battery_resistance_ohm;
    } else {
        t.kind = MotorTerminal::Kind::open;
        t.clamp_V = source_V + 2.0 * p.flyback_diode_drop_V;
        t.series_resistance_ohm = battery_resistance_ohm;
    }
    return t;
}

}  // namespace ddmr::plant
