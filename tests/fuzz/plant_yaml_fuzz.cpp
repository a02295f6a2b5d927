// Fuzz target: the plant/board parameter loader (plant/params_yaml,
// hil/board) on arbitrary text. Anything but a clean ParamsFileError /
// std::invalid_argument / std::runtime_error refusal is a finding.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "plant/params_yaml.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        const auto params = ddmr::plant::parse_robot_params(text, "fuzz.yaml");
        ddmr::plant::validate(params);  // what was accepted must be valid
    } catch (const std::runtime_error&) {
    } catch (const std::invalid_argument&) {
    }
    return 0;
}
