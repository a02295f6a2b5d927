#include "SoftStart.h"

SoftStart::SoftStart(uint8_t target, unsigned long ramp_ms) : target_(target), ramp_ms_(ramp_ms), start_ms_(0) {}

void SoftStart::begin() { start_ms_ = millis(); }

uint8_t SoftStart::duty() const {
    const unsigned long t = millis() - start_ms_;
    if (t >= ramp_ms_) return target_;
    return (uint8_t)((unsigned long)target_ * t / ramp_ms_);
}
