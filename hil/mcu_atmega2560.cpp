// The ATmega2560 (Arduino Mega 2560) as data. Source: Atmel ATmega640/1280/
// 1281/2560/2561 datasheet 2549Q: "Register Summary" (data-space addresses =
// I/O address + 0x20), Table 14-1 "Reset and Interrupt Vectors", section 13.3
// "Alternate Port Functions", Tables 16-x/17-x (timers), chapter 22 (USART),
// "Memories" (8 KiB SRAM from 0x200, 4 KiB EEPROM, 256 KiB flash); the names
// and addresses agree with avr-libc's <avr/iomxx0_1.h>.
#include "hil/atmega328p.hpp"
#include "hil/mcu.hpp"

namespace ddmr::hil {
namespace {

using avr_timers_detail::pin;

PortRegisters port(char letter, uint16_t pin_address) {
    // PINx, DDRx, PORTx are consecutive in every port of the ATmega2560.
    return {letter, pin_address, static_cast<uint16_t>(pin_address + 1), static_cast<uint16_t>(pin_address + 2)};
}

/// A 16-bit timer with three channels at `base` (TCCRnA); Timer1/3/4/5 lay
/// their registers out alike: TCCRnA/B/C +0..2, TCNTn +4, ICRn +6, OCRnA/B/C +8/+10/+12.
TimerDesc timer16(int index, uint16_t base, PortBit a, PortBit b, PortBit c) {
    TimerDesc d = avr_timers_detail::timer1();
    d.index = index;
    d.tccra = base;
    d.tccrb = static_cast<uint16_t>(base + 1);
    d.tcnt_low = static_cast<uint16_t>(base + 4);
    d.tcnt_high = static_cast<uint16_t>(base + 5);
    d.icr_low = static_cast<uint16_t>(base + 6);
    d.icr_high = static_cast<uint16_t>(base + 7);
    d.ocra_low = static_cast<uint16_t>(base + 8);
    d.ocra_high = static_cast<uint16_t>(base + 9);
    d.ocrb_low = static_cast<uint16_t>(base + 10);
    d.ocrb_high = static_cast<uint16_t>(base + 11);
    d.ocrc_low = static_cast<uint16_t>(base + 12);
    d.ocrc_high = static_cast<uint16_t>(base + 13);
    d.channels = 3;
    d.pins = {a, b, c};
    return d;
}

McuDescription make_atmega2560() {
    namespace reg = atmega328p::reg;  // EIMSK, EIFR, PCICR, PCIFR, PCMSK0 sit at the same addresses
    McuDescription d;
    d.name = "atmega2560";
    d.label = "ATmega2560";
    d.elf_arch = 6;  // EF_AVR_ARCH_AVR6: 3-byte PC
    d.flash_bytes = 256 * 1024;
    d.sram_bytes = 8 * 1024;
    d.sram_start = 0x0200;  // after the extended I/O space (0x60..0x1FF)
    d.ram_end = 0x21FF;
    d.eeprom_bytes = 4096;
    d.vector_bytes = 4;
    d.vector_names = {"RESET",        "INT0",         "INT1",         "INT2",         "INT3",
                      "INT4",         "INT5",         "INT6",         "INT7",         "PCINT0",
                      "PCINT1",       "PCINT2",       "WDT",          "TIMER2_COMPA", "TIMER2_COMPB",
                      "TIMER2_OVF",   "TIMER1_CAPT",  "TIMER1_COMPA", "TIMER1_COMPB", "TIMER1_COMPC",
                      "TIMER1_OVF",   "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF",   "SPI_STC",
                      "USART0_RX",    "USART0_UDRE",  "USART0_TX",    "ANALOG_COMP",  "ADC",
                      "EE_READY",     "TIMER3_CAPT",  "TIMER3_COMPA", "TIMER3_COMPB", "TIMER3_COMPC",
                      "TIMER3_OVF",   "USART1_RX",    "USART1_UDRE",  "USART1_TX",    "TWI",
                      "SPM_READY",    "TIMER4_CAPT",  "TIMER4_COMPA", "TIMER4_COMPB", "TIMER4_COMPC",
                      "TIMER4_OVF",   "TIMER5_CAPT",  "TIMER5_COMPA", "TIMER5_COMPB", "TIMER5_COMPC",
                      "TIMER5_OVF",   "USART2_RX",    "USART2_UDRE",  "USART2_TX",    "USART3_RX",
                      "USART3_UDRE",  "USART3_TX"};
    // A 22-bit PC: CALL, RCALL and interrupts push 3 bytes, RET and RETI take
    // 5 cycles (instruction set summary, devices with 22-bit PC).
    d.pc_bytes = 3;
    d.reti_cycles = 5;
    set_megaavr_core_registers(d);
    d.twi_sda = {'D', 1};  // PD1 (SDA/INT1), PD0 (SCL/INT0): ATmega2560 datasheet section 13.3.4
    d.twi_scl = {'D', 0};
    d.ports = {port('A', 0x20), port('B', 0x23),  port('C', 0x26),  port('D', 0x29),
               port('E', 0x2C), port('F', 0x2F),  port('G', 0x32),  port('H', 0x100),
               port('J', 0x103), port('K', 0x106), port('L', 0x109)};
    // INT0-3 = PD0-3, INT4-7 = PE4-7 (13.3.4, 13.3.5); ISC of INT0-3 in EICRA, INT4-7 in EICRB.
    d.ext_int_pins = {{'D', 0}, {'D', 1}, {'D', 2}, {'D', 3}, {'E', 4}, {'E', 5}, {'E', 6}, {'E', 7}};
    d.int0_vector = 1;
    d.eicr = {0x69, 0x6A};
    d.eimsk = reg::kEimsk;
    d.eifr = reg::kEifr;
    // PCINT0-7 = PB0-7, PCINT8 = PE0, PCINT9-15 = PJ0-6, PCINT16-23 = PK0-7.
    d.pcint_pins.resize(24);
    for (uint8_t b = 0; b < 8; ++b) {
        d.pcint_pins[b] = PortBit{'B', b};
        d.pcint_pins[16U + b] = PortBit{'K', b};
        if (b < 7) d.pcint_pins[9U + b] = PortBit{'J', b};
    }
    d.pcint_pins[8] = PortBit{'E', 0};
    d.pcint0_vector = 9;
    d.pcicr = reg::kPcicr;
    d.pcifr = reg::kPcifr;
    d.pcmsk0 = reg::kPcmsk0;
    // Timer0 and Timer2 are the ATmega328P's (same registers and modes) on other pins.
    TimerDesc t0 = avr_timers_detail::timer0();
    t0.pins = {pin('B', 7), pin('G', 5), PortBit{}};  // OC0A, OC0B
    TimerDesc t2 = avr_timers_detail::timer2();
    t2.pins = {pin('B', 4), pin('H', 6), PortBit{}};  // OC2A, OC2B
    d.timers = {t0,
                timer16(1, 0x80, pin('B', 5), pin('B', 6), pin('B', 7)),
                t2,
                timer16(3, 0x90, pin('E', 3), pin('E', 4), pin('E', 5)),
                timer16(4, 0xA0, pin('H', 3), pin('H', 4), pin('H', 5)),
                timer16(5, 0x120, pin('L', 3), pin('L', 4), pin('L', 5))};
    d.usarts = {megaavr_usart(0, 0xC0, 25, {'E', 0}, {'E', 1}), megaavr_usart(1, 0xC8, 36, {'D', 2}, {'D', 3}),
                megaavr_usart(2, 0xD0, 51, {'H', 0}, {'H', 1}), megaavr_usart(3, 0x130, 54, {'J', 0}, {'J', 1})};
    // ADC (2549Q section 26.8.1, Table 26-3): ADMUX and ADCSRA at the
    // ATmega328P's addresses; 16 inputs (MUX5 in ADCSRB selects ADC8..15);
    // REFS1:0 00 AREF, 01 AVCC, 10 internal 1.1 V, 11 internal 2.56 V.
    d.adc.admux = atmega328p::reg::kAdmux;
    d.adc.adcsra = atmega328p::reg::kAdcsra;
    d.adc.channels = 16;
    d.adc.refs = {{{AdcRefKind::aref, 0.0},
                   {AdcRefKind::avcc, 0.0},
                   {AdcRefKind::internal, 1.1},
                   {AdcRefKind::internal, 2.56}}};
    return d;
}

}  // namespace

const McuDescription& atmega2560_mcu() {
    static const McuDescription d = make_atmega2560();
    return d;
}

}  // namespace ddmr::hil
