// Fuzz target: the EEPROM log decoder (hil/eeprom_log) on an arbitrary
// 1024-byte image and sample count.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "hil/eeprom_log.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    ddmr::hil::EepromImage image(ddmr::hil::atmega328p_mcu().eeprom_bytes, 0xFF);
    std::memcpy(image.data(), data, std::min(size, image.size()));
    const int count = size > image.size() ? static_cast<int>(data[image.size()]) : static_cast<int>(size % 260);
    try {
        const auto samples = ddmr::hil::decode_eeprom_log(image, count);
        if (samples.size() != static_cast<std::size_t>(count)) __builtin_trap();
        (void)ddmr::hil::eeprom_log_csv(samples);
    } catch (const std::invalid_argument&) {
        if (count >= 0 && count <= 250) __builtin_trap();  // a valid count must decode
    }
    return 0;
}
