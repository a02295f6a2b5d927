#include "hil/uno_pins.hpp"

#include <array>
#include <cctype>

namespace ddmr::hil {
namespace {

// Data-space addresses (I/O address + 0x20), datasheet register summary.
constexpr uint16_t kPinB = 0x23;
constexpr uint16_t kPinC = 0x26;
constexpr uint16_t kPinD = 0x29;

/// OC units by pin (Figure 1-1): D6 OC0A, D5 OC0B, D9 OC1A, D10 OC1B,
/// D11 OC2A, D3 OC2B.
std::optional<OcChannel> oc_of(int number) {
    switch (number) {
        case 6: return OcChannel{0, 0};
        case 5: return OcChannel{0, 1};
        case 9: return OcChannel{1, 0};
        case 10: return OcChannel{1, 1};
        case 11: return OcChannel{2, 0};
        case 3: return OcChannel{2, 1};
        default: return std::nullopt;
    }
}

}  // namespace

std::optional<UnoPin> uno_pin(int number) {
    if (number < 0 || number >= kUnoPinCount) return std::nullopt;
    UnoPin p;
    p.number = number;
    uint16_t pin_reg = kPinD;
    if (number <= 7) {
        p.port = 'D';
        p.bit = number;
        p.pcint_group = 2;
    } else if (number <= 13) {
        p.port = 'B';
        p.bit = number - 8;
        pin_reg = kPinB;
        p.pcint_group = 0;
    } else {
        p.port = 'C';
        p.bit = number - 14;
        pin_reg = kPinC;
        p.pcint_group = 1;
    }
    // PINx, DDRx, PORTx are consecutive in every port.
    p.pin_register = pin_reg;
    p.ddr_register = static_cast<uint16_t>(pin_reg + 1);
    p.port_register = static_cast<uint16_t>(pin_reg + 2);
    p.pcint_bit = p.bit;
    p.oc = oc_of(number);
    if (number == 2) p.ext_int = 0;
    if (number == 3) p.ext_int = 1;
    return p;
}

std::optional<int> parse_uno_pin_name(const std::string& name) {
    if (name.empty()) return std::nullopt;
    std::string digits = name;
    int offset = 0;
    if (name[0] == 'A' || name[0] == 'a') {
        digits = name.substr(1);
        offset = 14;
    } else if (name[0] == 'D' || name[0] == 'd') {
        digits = name.substr(1);
    }
    if (digits.empty() || digits.size() > 2) return std::nullopt;
    int n = 0;
    for (const char c : digits) {
        if (std::isdigit(static_cast<unsigned char>(c)) == 0) return std::nullopt;
        n = n * 10 + (c - '0');
    }
    if (offset == 14 && n > 5) return std::nullopt;  // A6/A7: analog-only (Nano)
    n += offset;
    if (n >= kUnoPinCount) return std::nullopt;
    return n;
}

std::string uno_pin_label(int number) {
    if (number >= 14) return "A" + std::to_string(number - 14);
    return "D" + std::to_string(number);
}

std::string sketch_pin_name(int number) {
    if (number >= 14) return uno_pin_label(number);
    return std::to_string(number);
}

std::string oc_name(const OcChannel& oc) {
    return "OC" + std::to_string(oc.timer) + (oc.channel == 0 ? "A" : "B");
}

}  // namespace ddmr::hil
