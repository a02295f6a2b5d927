// quadrature: two channels 90 degrees apart (A leads B going forward), each
// changing level at the plant encoder's edges. docs/boards.md "Encoders".
#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/wheel_part_type.hpp"

namespace ddmr::hil {

PartType encoder_quadrature_type() {
    return encoder_type("quadrature", "two-channel quadrature encoder: A leads B going forward",
                        "docs/plant.md (the encoder's edges per motor turn)",
                        EncoderSpec{EncoderKind::quadrature, {"A", "B"}},
                        {"channel A's output pin", "channel B's output pin"},
                        "true: the channels are swapped (B leads A going forward)");
}

}  // namespace ddmr::hil
