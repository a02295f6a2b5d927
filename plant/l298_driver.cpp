#include "plant/l298_driver.hpp"

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

}  // namespace ddmr::plant
