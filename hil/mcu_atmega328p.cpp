// The ATmega328P as data, from the named constants of hil/atmega328p.hpp and
// hil/avr_timers.hpp (datasheet 7810D: register summary, Table 12-6
// "Reset and Interrupt Vectors", Figure 1-1 "Pinout", section 13.3
// "Alternate Port Functions", chapter 20 "USART0").
#include "hil/atmega328p.hpp"
#include "hil/mcu.hpp"

namespace ddmr::hil {
namespace {

McuDescription make_atmega328p() {
    namespace chip = atmega328p;
    namespace reg = atmega328p::reg;
    McuDescription d;
    d.name = chip::kMcuName;
    d.label = "ATmega328P";
    d.elf_arch = chip::kElfArchAvr5;
    d.flash_bytes = chip::kFlashBytes;
    d.sram_bytes = chip::kSramBytes;
    d.sram_start = chip::kSramStart;
    d.ram_end = chip::kRamEnd;
    d.eeprom_bytes = chip::kEepromBytes;
    d.vector_bytes = chip::kVectorBytes;
    d.vector_names.assign(chip::vector::kNames.begin(), chip::vector::kNames.end());
    d.reti_cycles = chip::kRetiCycles;
    set_megaavr_core_registers(d);
    d.twi_sda = {'C', 4};  // PC4 (SDA), PC5 (SCL): datasheet section 1.1.3
    d.twi_scl = {'C', 5};
    d.ports = {{'B', reg::kPinB, reg::kDdrB, reg::kPortB},
               {'C', reg::kPinC, reg::kDdrC, reg::kPortC},
               {'D', reg::kPinD, reg::kDdrD, reg::kPortD}};
    // INT0 = PD2, INT1 = PD3 (section 13.3.3).
    d.ext_int_pins = {{'D', 2}, {'D', 3}};
    d.int0_vector = chip::vector::kInt0;
    d.eicr = {reg::kEicra};
    d.eimsk = reg::kEimsk;
    d.eifr = reg::kEifr;
    // PCINT0-7 = PB0-PB7, PCINT8-14 = PC0-PC6, PCINT16-23 = PD0-PD7
    // (PCINT15 does not exist).
    d.pcint_pins.resize(24);
    for (uint8_t b = 0; b < 8; ++b) {
        d.pcint_pins[b] = PortBit{'B', b};
        if (b < 7) d.pcint_pins[8U + b] = PortBit{'C', b};
        d.pcint_pins[16U + b] = PortBit{'D', b};
    }
    d.pcint0_vector = chip::vector::kPcint0;
    d.pcicr = reg::kPcicr;
    d.pcifr = reg::kPcifr;
    d.pcmsk0 = reg::kPcmsk0;
    d.timers.assign(kAtmega328pTimers.begin(), kAtmega328pTimers.end());
    // USART0 (chapter 20): UCSR0A at 0xC0 .. UDR0 at 0xC6, RXD0 = PD0, TXD0 = PD1.
    static_assert(reg::kUdr0 == reg::kUcsr0A + 6 && reg::kUbrr0L == reg::kUcsr0A + 4, "USART0 layout");
    d.usarts = {megaavr_usart(0, reg::kUcsr0A, chip::vector::kUsartRx, {'D', 0}, {'D', 1})};
    // ADC (section 24.9.1, Table 24-3 "Voltage Reference Selections"):
    // 00 AREF, 01 AVCC with a capacitor at AREF, 10 reserved, 11 internal 1.1 V.
    d.adc.admux = reg::kAdmux;
    d.adc.adcsra = reg::kAdcsra;
    d.adc.channels = chip::kAdcChannels;
    d.adc.refs = {{{AdcRefKind::aref, 0.0},
                   {AdcRefKind::avcc, 0.0},
                   {AdcRefKind::reserved, 0.0},
                   {AdcRefKind::internal, chip::kInternalRefV}}};
    return d;
}

}  // namespace

const McuDescription& atmega328p_mcu() {
    static const McuDescription d = make_atmega328p();
    return d;
}

}  // namespace ddmr::hil
