// A scenario step's kind to its family's parser (step_parsers.hpp).
#include "scenario/step_parsers.hpp"

#include <stdexcept>

#include "scenario/step_catalog.hpp"

namespace ddmr::tools::scenario::yaml {

StepAction parse_step(const std::string& kind, const Ctx& c) {
    if (find_step(kind) == nullptr) {
        std::string kinds;
        for (const StepInfo& i : step_catalog()) kinds += (kinds.empty() ? "" : ", ") + std::string(i.kind);
        c.fail(fmt::format("unknown step (the steps: {}; `ddmr-hil scenario --list-steps` shows their forms)", kinds));
    }
    for (const auto parse : {parse_serial_step, parse_pin_step, parse_firmware_step, parse_plant_step,
                             parse_fault_step}) {
        if (std::optional<StepAction> action = parse(kind, c)) return std::move(*action);
    }
    // A kind in the catalogue that no family parses: a programming error.
    throw std::logic_error("scenario step '" + kind + "' is in the catalogue but not parsed");
}

}  // namespace ddmr::tools::scenario::yaml
