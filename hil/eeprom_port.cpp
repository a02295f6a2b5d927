#include "hil/eeprom_port.hpp"

#include <avr_eeprom.h>
#include <sim_avr.h>

#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>

#include "hil/atmega328p.hpp"

namespace ddmr::hil {
namespace {

/// simavr 1.6 returns -2 for bad arguments. On success it returns -1, the same
/// value avr_ioctl gives when no module handled the call, so success is checked
/// by reading back (preload) or by the descriptor being filled (read).
constexpr int kIoctlBadArguments = -2;

}  // namespace

EepromImage EepromPort::read_all() const {
    EepromImage image(core_.mcu().eeprom_bytes, 0);
    avr_eeprom_desc_t desc{image.data(), 0, static_cast<uint32_t>(image.size())};
    const int rc = avr_ioctl(core_.raw(), AVR_IOCTL_EEPROM_GET, &desc);
    if (rc == kIoctlBadArguments) throw std::runtime_error("simavr refused to read the EEPROM");
    return image;
}

void EepromPort::preload(const EepromImage& image) {
    if (image.size() != core_.mcu().eeprom_bytes) {
        throw std::invalid_argument("EEPROM preload of " + std::to_string(image.size()) + " bytes: the " +
                                    core_.mcu().label + " has " + std::to_string(core_.mcu().eeprom_bytes));
    }
    EepromImage copy = image;  // simavr takes a non-const pointer
    avr_eeprom_desc_t desc{copy.data(), 0, static_cast<uint32_t>(copy.size())};
    const int rc = avr_ioctl(core_.raw(), AVR_IOCTL_EEPROM_SET, &desc);
    if (rc == kIoctlBadArguments || read_all() != image) {
        throw std::runtime_error("simavr refused the EEPROM preload");
    }
}

EepromImage EepromPort::load_image(const std::filesystem::path& path, const McuDescription& mcu) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("EEPROM image " + path.string() + ": cannot open");
    std::vector<char> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (bytes.size() != mcu.eeprom_bytes) {
        throw std::runtime_error("EEPROM image " + path.string() + ": " + std::to_string(bytes.size()) +
                                 " bytes, the " + mcu.label + " has " + std::to_string(mcu.eeprom_bytes));
    }
    EepromImage image(bytes.size());
    for (std::size_t i = 0; i < image.size(); ++i) image[i] = static_cast<uint8_t>(bytes[i]);
    return image;
}

EepromImage EepromPort::erased(const McuDescription& mcu) {
    return EepromImage(mcu.eeprom_bytes, atmega328p::kEepromErased);
}

}  // namespace ddmr::hil
