#include "hil/mcu.hpp"

namespace ddmr::hil {
namespace {

bool same(PortBit a, PortBit b) { return a.port == b.port && a.bit == b.bit; }

}  // namespace

std::string McuDescription::vector_name(int vector) const {
    if (vector >= 0 && vector < vector_count()) return vector_names[static_cast<std::size_t>(vector)];
    return "vector " + std::to_string(vector);
}

const PortRegisters* McuDescription::port(char letter) const {
    for (const PortRegisters& p : ports) {
        if (p.port == letter) return &p;
    }
    return nullptr;
}

std::optional<int> McuDescription::ext_int_at(PortBit pin) const {
    for (std::size_t n = 0; n < ext_int_pins.size(); ++n) {
        if (same(ext_int_pins[n], pin)) return static_cast<int>(n);
    }
    return std::nullopt;
}

std::optional<int> McuDescription::pcint_at(PortBit pin) const {
    for (std::size_t k = 0; k < pcint_pins.size(); ++k) {
        if (pcint_pins[k] && same(*pcint_pins[k], pin)) return static_cast<int>(k);
    }
    return std::nullopt;
}

std::optional<OcChannel> McuDescription::oc_at(PortBit pin) const {
    for (const TimerDesc& t : timers) {
        for (std::size_t c = 0; c < t.pins.size(); ++c) {
            if (same(t.pins[c], pin)) return OcChannel{t.index, static_cast<int>(c)};
        }
    }
    return std::nullopt;
}

std::string oc_name(const OcChannel& oc) {
    return "OC" + std::to_string(oc.timer) + static_cast<char>('A' + oc.channel);
}

}  // namespace ddmr::hil
