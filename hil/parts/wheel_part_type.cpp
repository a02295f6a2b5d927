#include "hil/parts/wheel_part_type.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "plant/bridge_driver.hpp"
#include "plant/hall_encoder.hpp"

namespace ddmr::hil {
namespace {

bool has(const std::vector<DriverRole>& v, DriverRole r) { return std::find(v.begin(), v.end(), r) != v.end(); }

/// A parameter table's keys, "a, b, c" (the plant file's names, from the table the file is read with).
template <class Table>
std::string key_list(const Table& fields) {
    std::string out;
    for (const auto& f : fields) out += (out.empty() ? "" : ", ") + std::string(f.key);
    return out;
}

PartKey wheel_key(const char* what) {
    PartKey k = PartKey::choice("wheel", std::string("the wheel whose ") + what + " it is (wheels: names it instead)",
                                {"right", "left"});
    k.required = true;
    return k;
}

}  // namespace

PartType motor_driver_type(std::string word, std::string summary, std::string datasheet, MotorDriverSpec spec,
                           const std::vector<std::pair<DriverRole, std::string>>& inputs) {
    PartType t;
    t.type = std::move(word);
    t.summary = std::move(summary);
    t.datasheet = std::move(datasheet);
    t.keys.push_back(wheel_key("motor"));
    for (const auto& [role, description] : inputs) {
        std::string d = description;
        if (has(spec.may_be_high, role)) d += "; `high`: tied high, no pin";
        if (has(spec.pwm_only, role)) d += "; a pin with a timer output";
        if (has(spec.optional_high, role)) {
            t.keys.push_back(PartKey::input_or(role_key(role), d, "high"));
        } else if (has(spec.required, role)) {
            t.keys.push_back(PartKey::input(role_key(role), d));
        } else {
            throw std::logic_error(t.type + ": input " + role_key(role) + " is in neither list");
        }
    }
    t.keys.push_back(PartKey::choice("reversed", "true: the motor leads are swapped (the bridge's forward turns the "
                                                 "wheel backwards)",
                                     {"false", "true"}));
    t.plant_parameters = fmt::format("the plant file's `{}:` section ({}), shared by both wheels' drivers of this chip",
                                     plant::params_section(plant::chip_of(spec.type)), key_list(plant::bridge_fields()));
    t.motor_driver = std::move(spec);
    return t;
}

PartType encoder_type(std::string word, std::string summary, std::string datasheet, EncoderSpec spec,
                      const std::vector<std::string>& descriptions, std::string reversed_means) {
    PartType t;
    t.type = std::move(word);
    t.summary = std::move(summary);
    t.datasheet = std::move(datasheet);
    t.keys.push_back(wheel_key("encoder"));
    for (std::size_t i = 0; i < spec.signals.size(); ++i) t.keys.push_back(PartKey::output(spec.signals[i], descriptions.at(i)));
    t.keys.push_back(PartKey::choice("reversed", std::move(reversed_means), {"false", "true"}));
    t.plant_parameters = "the plant file's `encoder1:` (right wheel) or `encoder2:` (left wheel) section: " +
                         key_list(plant::hall_encoder_fields());
    t.encoder = std::move(spec);
    return t;
}

}  // namespace ddmr::hil
