#include "plant/robot_params.hpp"

#include <stdexcept>
#include <string>
#include <variant>

namespace ddmr::plant {

const std::array<Field<StepperConfig>, 2>& stepper_fields() {
    using P = StepperConfig;
    static const std::array<Field<P>, 2> table{{
        {"max_step_s", "s", positive(0.01), &P::max_step_s},
        {"event_step_s", "s", positive(0.01), &P::event_step_s},
    }};
    return table;
}

void validate(const StepperConfig& p, const char* prefix) {
    validate_fields(p, stepper_fields(), prefix);
}

RobotParams default_robot_params() {
    RobotParams p;
    // Motor 2 differs from motor 1 only where Table 2 measured it.
    p.motor[1].resistance_ohm = 5.41;
    p.motor[1].inductance_H = 2.4e-3;
    p.encoder[1].seed = 2;
    return p;
}

void validate(const RobotParams& p) {
    for_each_section(p, [](const char* name, const auto& part, const auto&) { validate(part, name); });
    for (std::size_t m = 0; m < p.chip.size(); ++m) {
        if (p.chip[m] != DriverChip::l298 && p.chip[m] != DriverChip::tb6612 &&
            p.chip[m] != DriverChip::drv8833 && p.chip[m] != DriverChip::l293d && p.chip[m] != DriverChip::l9110) {
            throw std::invalid_argument("invalid plant parameter chip[" + std::to_string(m) +
                                        "] = " + std::to_string(static_cast<int>(p.chip[m])) +
                                        ": not a known driver chip");
        }
    }
}


namespace {
template <class P, std::size_t N>
bool fields_equal(const P& a, const P& b, const std::array<Field<P>, N>& table) {
    bool equal = true;
    for (const Field<P>& f : table) {
        std::visit([&](auto m) { equal = equal && (a.*m == b.*m); }, f.member);
    }
    return equal;
}
}  // namespace

bool operator==(const RobotParams& a, const RobotParams& b) {
    return fields_equal(a.motor[0], b.motor[0], dc_motor_fields()) &&
           fields_equal(a.motor[1], b.motor[1], dc_motor_fields()) &&
           fields_equal(a.driver, b.driver, bridge_fields()) &&
           fields_equal(a.tb6612, b.tb6612, bridge_fields()) &&
           fields_equal(a.drv8833, b.drv8833, bridge_fields()) &&
           fields_equal(a.l293d, b.l293d, bridge_fields()) &&
           fields_equal(a.l9110, b.l9110, bridge_fields()) && a.chip == b.chip &&
           fields_equal(a.battery, b.battery, battery_fields()) &&
           fields_equal(a.encoder[0], b.encoder[0], hall_encoder_fields()) &&
           fields_equal(a.encoder[1], b.encoder[1], hall_encoder_fields()) &&
           a.encoder[0].channels == b.encoder[0].channels &&
           a.encoder[1].channels == b.encoder[1].channels &&
           fields_equal(a.kinematics, b.kinematics, diff_drive_fields()) &&
           fields_equal(a.body, b.body, body_fields()) &&
           fields_equal(a.stepper, b.stepper, stepper_fields());
}

}  // namespace ddmr::plant
