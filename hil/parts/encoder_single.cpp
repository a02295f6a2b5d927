// single: one Hall or slotted-disc channel per wheel (OUT), a level change
// at each of the plant encoder's edges. docs/boards.md "Encoders".
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType encoder_single_type() {
    return encoder_type("single", "one-channel encoder (Hall sensor or slotted disc): OUT changes at each edge",
                        "docs/plant.md (the encoder's edges per motor turn)",
                        EncoderSpec{EncoderKind::single, {"OUT"}}, {"the output pin the encoder drives"},
                        "no meaning for one channel (accepted, ignored)");
}

}  // namespace ddmr::hil
