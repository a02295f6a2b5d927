#pragma once
// EepromPort: host access to the EEPROM of an AvrCore's MCU (1 KiB on the
// ATmega328P, 4 KiB on the ATmega2560),
// through simavr's EEPROM ioctls. A preload is what a previous run (or the
// factory, 0xFF) left in the chip; the firmware sees it on its first read.

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "hil/avr_core.hpp"

namespace ddmr::hil {

/// The whole EEPROM, McuDescription::eeprom_bytes bytes.
using EepromImage = std::vector<uint8_t>;

class EepromPort {
public:
    explicit EepromPort(AvrCore& core) : core_(core) {}

    /// Every byte as the firmware would read them now.
    EepromImage read_all() const;

    /// Replaces the whole EEPROM. Throws std::invalid_argument if the image is
    /// not the MCU's size, std::runtime_error if simavr refuses.
    void preload(const EepromImage& image);

    /// Reads a preload image from a file; it must hold exactly the MCU's
    /// EEPROM size. Throws std::runtime_error naming the file and both sizes otherwise.
    static EepromImage load_image(const std::filesystem::path& path, const McuDescription& mcu);

    /// An erased EEPROM (every byte 0xFF), as a new chip has.
    static EepromImage erased(const McuDescription& mcu);

private:
    AvrCore& core_;
};

}  // namespace ddmr::hil
