#include "plant/robot_faults.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace ddmr::plant {

void validate(const RobotFaults& f) {
    if (f.source_V && !(*f.source_V > 0.0 && *f.source_V <= 50.0)) {
        throw std::invalid_argument("battery source voltage " + std::to_string(*f.source_V) +
                                    " V: must be in (0, 50] V");
    }
    for (std::size_t m = 0; m < f.traction.size(); ++m) {
        if (!(f.traction[m] >= 0.0 && f.traction[m] <= 1.0)) {
            throw std::invalid_argument("traction of wheel " + std::to_string(m + 1) + " = " +
                                        std::to_string(f.traction[m]) + ": must be in [0, 1]");
        }
    }
}

}  // namespace ddmr::plant
