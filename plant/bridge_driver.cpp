#include "plant/bridge_driver.hpp"

namespace ddmr::plant {

const std::array<Field<BridgeParams>, 4>& bridge_fields() {
    using P = BridgeParams;
    static const std::array<Field<P>, 4> table{{
        {"drop_V", "V", non_negative(5.0), &P::drop_V},
        {"on_resistance_ohm", "ohm", non_negative(10.0), &P::on_resistance_ohm},
        {"brake_resistance_ohm", "ohm", non_negative(10.0), &P::brake_resistance_ohm},
        {"flyback_diode_drop_V", "V", non_negative(3.0), &P::flyback_diode_drop_V},
    }};
    return table;
}

void validate(const BridgeParams& p, const char* prefix) { validate_fields(p, bridge_fields(), prefix); }

}  // namespace ddmr::plant
