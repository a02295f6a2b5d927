#include "tools/hostsim/fidelity.hpp"

#include <stdexcept>

namespace ddmr::hostsim {

namespace {

std::string known_names() {
    std::string s;
    for (const char* n : fidelity_switch_names()) {
        if (!s.empty()) s += ", ";
        s += n;
    }
    return s;
}

std::string trimmed(const std::string& s) {
    const auto first = s.find_first_not_of(" \t");
    if (first == std::string::npos) return {};
    const auto last = s.find_last_not_of(" \t");
    return s.substr(first, last - first + 1);
}

}  // namespace

const std::array<const char*, kFidelitySwitchCount>& fidelity_switch_names() {
    static const std::array<const char*, kFidelitySwitchCount> names = {
        "int_gains",         "float32",          "encoder_odometry", "loop_period",
        "feedforward_constants", "pwm_quantisation", "eeprom_bytes",
    };
    return names;
}

const char* to_string(FidelitySwitch s) {
    return fidelity_switch_names()[static_cast<std::size_t>(s)];
}

Fidelity Fidelity::all() {
    Fidelity f;
    f.bits_.set();
    return f;
}

Fidelity Fidelity::parse(const std::string& list) {
    const std::string whole = trimmed(list);
    if (whole.empty() || whole == "none") return none();
    if (whole == "all") return all();
    Fidelity f;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = whole.find(',', start);
        const std::string item =
            trimmed(whole.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
        if (item.empty()) {
            throw std::invalid_argument("fidelity list '" + list +
                                        "' has an empty element (known switches: " + known_names() + ")");
        }
        bool found = false;
        for (std::size_t k = 0; k < kFidelitySwitchCount; ++k) {
            if (item == fidelity_switch_names()[k]) {
                f.bits_.set(k);
                found = true;
            }
        }
        if (!found) {
            throw std::invalid_argument("unknown fidelity switch '" + item +
                                        "' (known: " + known_names() + ", or all, none)");
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
    }
    return f;
}

std::vector<std::string> Fidelity::names() const {
    std::vector<std::string> out;
    for (std::size_t k = 0; k < kFidelitySwitchCount; ++k) {
        if (bits_.test(k)) out.emplace_back(fidelity_switch_names()[k]);
    }
    return out;
}

std::string Fidelity::to_string() const {
    std::string s;
    for (const std::string& n : names()) {
        if (!s.empty()) s += ",";
        s += n;
    }
    return s.empty() ? "none" : s;
}

}  // namespace ddmr::hostsim
