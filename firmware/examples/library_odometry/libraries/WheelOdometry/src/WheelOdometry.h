#pragma once
// Encoder counts to wheel travel: counts_per_turn edges per wheel turn on a
// wheel of the given diameter.
#include <stdint.h>

class WheelOdometry {
public:
    WheelOdometry(uint16_t counts_per_turn, float wheel_diameter_mm);
    /// Travel [mm] of `counts` edges.
    float distance_mm(uint32_t counts) const;
    /// Edges for a travel of `mm`.
    uint32_t counts_for_mm(float mm) const;

private:
    float mm_per_count_;
};
