#include "hil/mcu.hpp"

#include "hil/atmega328p.hpp"

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
        for (std::size_t c = 0; c < static_cast<std::size_t>(t.channels); ++c) {
            if (same(t.pins[c], pin)) return OcChannel{t.index, static_cast<int>(c)};
        }
    }
    return std::nullopt;
}

UsartDesc megaavr_usart(int index, uint16_t ucsra, int rx_vector, PortBit rxd, PortBit txd) {
    UsartDesc u;
    u.index = index;
    u.ucsra = ucsra;
    u.ucsrb = static_cast<uint16_t>(ucsra + 1);
    u.ucsrc = static_cast<uint16_t>(ucsra + 2);
    u.ubrrl = static_cast<uint16_t>(ucsra + 4);
    u.ubrrh = static_cast<uint16_t>(ucsra + 5);
    u.udr = static_cast<uint16_t>(ucsra + 6);
    u.rx_vector = rx_vector;
    u.udre_vector = rx_vector + 1;
    u.tx_vector = rx_vector + 2;
    u.rxd = rxd;
    u.txd = txd;
    return u;
}

void set_megaavr_core_registers(McuDescription& d) {
    namespace reg = atmega328p::reg;
    d.spl = reg::kSpl;
    d.sph = reg::kSph;
    d.sreg = reg::kSreg;
    d.mcusr = reg::kMcusr;
    d.mcucr = reg::kMcucr;
    d.pud_bit = atmega328p::kPud;
    d.twsr = reg::kTwsr;
    d.twcr = reg::kTwcr;
    d.twbr = reg::kTwbr;
    d.eecr = reg::kEecr;
    d.eedr = reg::kEedr;
    d.eearl = reg::kEearL;
    d.eearh = reg::kEearH;
}

std::string oc_name(const OcChannel& oc) {
    return "OC" + std::to_string(oc.timer) + static_cast<char>('A' + oc.channel);
}

}  // namespace ddmr::hil
