// Fuzz target: the scenario loader (tools/scenario/scenario_yaml) on
// arbitrary text: it must refuse with a ScenarioError (or accept).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "scenario/scenario_yaml.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    ddmr::tools::scenario::LoadOptions options;
    options.reference_firmware = "/nonexistent/reference.elf";
    try {
        ddmr::tools::scenario::parse_scenario(text, "/tmp/fuzz/scenario.yaml", options);
    } catch (const ddmr::tools::scenario::ScenarioError&) {
    }
    return 0;
}
