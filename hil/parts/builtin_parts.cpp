#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/part_registry.hpp"

namespace ddmr::hil {

std::vector<PartType> builtin_part_types() {
    return {
        shift_register_74hc595_type(),
    };
}

}  // namespace ddmr::hil
