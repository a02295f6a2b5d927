#pragma once
// The L298 is one chip of the general bridge model: its truth tables are in
// motor_driver.hpp (DriverType::dir_pwm, DriverType::l298n), its electrical
// model and parameters in bridge_driver.hpp (DriverChip::l298, the `driver:`
// section of a plant file). This header stays for includers that need only
// DriveMode; new code includes bridge_driver.hpp.

#include "plant/bridge_driver.hpp"
