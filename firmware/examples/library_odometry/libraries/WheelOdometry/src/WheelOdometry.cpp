#include "WheelOdometry.h"

WheelOdometry::WheelOdometry(uint16_t counts_per_turn, float wheel_diameter_mm)
    : mm_per_count_(3.14159265f * wheel_diameter_mm / counts_per_turn) {}

float WheelOdometry::distance_mm(uint32_t counts) const { return counts * mm_per_count_; }

uint32_t WheelOdometry::counts_for_mm(float mm) const { return (uint32_t)(mm / mm_per_count_ + 0.5f); }
