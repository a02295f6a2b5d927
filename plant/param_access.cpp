#include "plant/param_access.hpp"

#include <type_traits>
#include <variant>

namespace ddmr::plant {

std::optional<ParamRef> find_param(RobotParams& p, std::string_view key) {
    std::optional<ParamRef> found;
    for_each_section(p, [&](const char* section, auto& part, const auto& table) {
        for (const auto& f : table) {
            std::visit(
                [&](auto member) {
                    using T = std::decay_t<decltype(part.*member)>;
                    if constexpr (std::is_same_v<T, double>) {
                        const std::string name = std::string(section) + "." + f.key;
                        if (name == key) found = ParamRef{name, &(part.*member), f.range, f.unit};
                    }
                },
                f.member);
        }
    });
    return found;
}

std::vector<std::string> param_keys() {
    RobotParams p = default_robot_params();
    std::vector<std::string> keys;
    for_each_section(p, [&](const char* section, auto& part, const auto& table) {
        for (const auto& f : table) {
            if (std::holds_alternative<double std::remove_reference_t<decltype(part)>::*>(f.member)) {
                keys.push_back(std::string(section) + "." + f.key);
            }
        }
    });
    return keys;
}

}  // namespace ddmr::plant
