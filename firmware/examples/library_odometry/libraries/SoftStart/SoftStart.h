#ifndef SOFT_START_H
#define SOFT_START_H
// A PWM ramp from 0 to a target duty over a time: a legacy (flat) library,
// no library.properties, header and source side by side.
#include <Arduino.h>

class SoftStart {
public:
    SoftStart(uint8_t target, unsigned long ramp_ms);
    void begin();
    /// The duty to write now.
    uint8_t duty() const;

private:
    uint8_t target_;
    unsigned long ramp_ms_;
    unsigned long start_ms_;
};
#endif
