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
    d.spl = reg::kSpl;
    d.sph = reg::kSph;
    d.sreg = reg::kSreg;
    d.mcusr = reg::kMcusr;
    d.eecr = reg::kEecr;
    d.eedr = reg::kEedr;
    d.eearl = reg::kEearL;
    d.eearh = reg::kEearH;
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
    UsartDesc u0;
    u0.index = 0;
    u0.ucsra = reg::kUcsr0A;
    u0.ucsrb = reg::kUcsr0B;
    u0.ucsrc = reg::kUcsr0C;
    u0.ubrrl = reg::kUbrr0L;
    u0.ubrrh = reg::kUbrr0H;
    u0.udr = reg::kUdr0;
    u0.rx_vector = chip::vector::kUsartRx;
    u0.udre_vector = chip::vector::kUsartUdre;
    u0.tx_vector = chip::vector::kUsartTx;
    u0.rxd = {'D', 0};
    u0.txd = {'D', 1};
    d.usarts = {u0};
    return d;
}

}  // namespace

const McuDescription& atmega328p_mcu() {
    static const McuDescription d = make_atmega328p();
    return d;
}

}  // namespace ddmr::hil
