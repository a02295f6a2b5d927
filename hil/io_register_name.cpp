#include "hil/io_register_name.hpp"

#include <fmt/format.h>

#include <optional>

#include "hil/mcu.hpp"

namespace ddmr::hil {
namespace {

/// A 16-bit register pair: NAME_L / NAME_H (an 8-bit timer has only NAME).
std::optional<std::string> pair_name(uint16_t a, uint16_t low, uint16_t high, const std::string& name) {
    if (low != 0 && a == low) return high != 0 ? name + "L" : name;
    if (high != 0 && a == high) return name + "H";
    return std::nullopt;
}

std::optional<std::string> timer_register(const McuDescription& mcu, uint16_t a) {
    for (const TimerDesc& t : mcu.timers) {
        const int n = t.index;
        if (a == t.tccra) return fmt::format("TCCR{}A", n);
        if (a == t.tccrb) return fmt::format("TCCR{}B", n);
        if (auto s = pair_name(a, t.tcnt_low, t.tcnt_high, fmt::format("TCNT{}", n))) return s;
        if (auto s = pair_name(a, t.ocra_low, t.ocra_high, fmt::format("OCR{}A", n))) return s;
        if (auto s = pair_name(a, t.ocrb_low, t.ocrb_high, fmt::format("OCR{}B", n))) return s;
        if (auto s = pair_name(a, t.ocrc_low, t.ocrc_high, fmt::format("OCR{}C", n))) return s;
        if (auto s = pair_name(a, t.icr_low, t.icr_high, fmt::format("ICR{}", n))) return s;
    }
    return std::nullopt;
}

std::optional<std::string> port_or_usart_register(const McuDescription& mcu, uint16_t a) {
    for (const PortRegisters& p : mcu.ports) {
        if (a == p.pin) return fmt::format("PIN{}", p.port);
        if (a == p.ddr) return fmt::format("DDR{}", p.port);
        if (a == p.port_register) return fmt::format("PORT{}", p.port);
    }
    for (const UsartDesc& u : mcu.usarts) {
        const int n = u.index;
        if (a == u.udr) return fmt::format("UDR{}", n);
        if (a == u.ucsra) return fmt::format("UCSR{}A", n);
        if (a == u.ucsrb) return fmt::format("UCSR{}B", n);
        if (a == u.ucsrc) return fmt::format("UCSR{}C", n);
        if (a == u.ubrrl) return fmt::format("UBRR{}L", n);
        if (a == u.ubrrh) return fmt::format("UBRR{}H", n);
    }
    return std::nullopt;
}

std::optional<std::string> core_register(const McuDescription& mcu, uint16_t a) {
    const std::pair<uint16_t, const char*> named[] = {
        {mcu.spl, "SPL"},       {mcu.sph, "SPH"},     {mcu.sreg, "SREG"},   {mcu.mcusr, "MCUSR"},
        {mcu.mcucr, "MCUCR"},   {mcu.twsr, "TWSR"},   {mcu.twcr, "TWCR"},   {mcu.twbr, "TWBR"},
        {mcu.eecr, "EECR"},     {mcu.eedr, "EEDR"},   {mcu.eearl, "EEARL"}, {mcu.eearh, "EEARH"},
        {mcu.eimsk, "EIMSK"},   {mcu.eifr, "EIFR"},   {mcu.pcicr, "PCICR"}, {mcu.pcifr, "PCIFR"},
        {mcu.adc.admux, "ADMUX"}, {mcu.adc.adcsra, "ADCSRA"},
    };
    for (const auto& [address, name] : named) {
        if (address != 0 && a == address) return std::string(name);
    }
    for (std::size_t i = 0; i < mcu.eicr.size(); ++i) {
        if (a == mcu.eicr[i]) return fmt::format("EICR{}", static_cast<char>('A' + i));
    }
    const std::size_t groups = (mcu.pcint_pins.size() + 7) / 8;
    if (mcu.pcmsk0 != 0 && a >= mcu.pcmsk0 && a < mcu.pcmsk0 + groups) return fmt::format("PCMSK{}", a - mcu.pcmsk0);
    return std::nullopt;
}

}  // namespace

std::string io_register_name(const McuDescription& mcu, uint16_t address) {
    if (auto s = port_or_usart_register(mcu, address)) return *s;
    if (auto s = timer_register(mcu, address)) return *s;
    if (auto s = core_register(mcu, address)) return *s;
    return fmt::format("I/O 0x{:02x}", address);
}

}  // namespace ddmr::hil
