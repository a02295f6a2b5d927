#pragma once
// EepromPort: host access to the ATmega328P's 1024-byte EEPROM of an AvrCore,
// through simavr's EEPROM ioctls. A preload is what a previous run (or the
// factory, 0xFF) left in the chip; the firmware sees it on its first read.

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "hil/atmega328p.hpp"
#include "hil/avr_core.hpp"

namespace ddmr::hil {

using EepromImage = std::array<uint8_t, atmega328p::kEepromBytes>;

class EepromPort {
public:
    explicit EepromPort(AvrCore& core) : core_(core) {}

    /// All 1024 bytes as the firmware would read them now.
    EepromImage read_all() const;

    /// Replaces the whole EEPROM. Throws std::runtime_error if simavr refuses.
    void preload(const EepromImage& image);

    /// Reads a preload image from a file; it must hold exactly 1024 bytes.
    /// Throws std::runtime_error naming the file and its size otherwise.
    static EepromImage load_image(const std::filesystem::path& path);

    /// An erased EEPROM (every byte 0xFF), as a new chip has.
    static EepromImage erased();

private:
    AvrCore& core_;
};

}  // namespace ddmr::hil
