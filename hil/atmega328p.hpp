#pragma once
// Facts about the ATmega328P that the HIL relies on, one named definition
// each; hil/mcu_atmega328p.cpp makes them the chip's McuDescription, which
// the parts read. The clock is the board's (hil/board_description.cpp).
// Addresses are AVR data-space addresses (I/O address + 0x20), as simavr uses.
// Source: ATmega328P datasheet (DS40002061B), register summary and memory map.

#include <array>
#include <cstdint>

namespace ddmr::hil::atmega328p {

inline constexpr const char* kMcuName = "atmega328p";
inline constexpr uint32_t kFlashBytes = 32 * 1024;
inline constexpr uint32_t kSramBytes = 2 * 1024;
inline constexpr uint16_t kSramStart = 0x0100;      ///< first SRAM address (after the I/O space)
inline constexpr uint16_t kRamEnd = 0x08FF;         ///< last SRAM address
inline constexpr uint32_t kEepromBytes = 1024;
inline constexpr uint8_t kEepromErased = 0xFF;      ///< value of an erased EEPROM byte
/// An EEPROM write from the CPU (atomic erase + write, EEPM = 00) is timed by the
/// calibrated RC oscillator, not the CPU clock: 26,368 cycles of it, typ. 3.3 ms.
/// Datasheet 7810D, section 8.6.3 "EECR", Table 8-2 "EEPROM Programming Time".
inline constexpr uint32_t kEepromWriteRcCycles = 26'368;
inline constexpr uint32_t kCalibratedRcHz = 8'000'000;  ///< calibrated RC oscillator [Hz]
inline constexpr int kVectorCount = 26;             ///< interrupt vectors incl. RESET
inline constexpr int kVectorBytes = 4;              ///< each vector is a JMP (2 words)
/// e_flags architecture of avr-gcc's -mmcu=atmega328p objects (EF_AVR_ARCH_AVR5).
inline constexpr unsigned kElfArchAvr5 = 5;

/// Interrupt vector numbers (datasheet table 12-6, 0 = RESET).
namespace vector {
inline constexpr int kInt0 = 1;
inline constexpr int kInt1 = 2;
inline constexpr int kPcint0 = 3;  ///< PCINT1 = 4, PCINT2 = 5: kPcint0 + group
inline constexpr int kTimer0Ovf = 16;
inline constexpr int kUsartRx = 18;
inline constexpr int kUsartUdre = 19;
inline constexpr int kUsartTx = 20;

/// Source names of every vector, datasheet table 12-6 ("Reset and Interrupt
/// Vectors in ATmega328P"), indexed by vector number; as in avr-libc's
/// <NAME>_vect with the "_vect" dropped.
inline constexpr std::array<const char*, kVectorCount> kNames = {
    "RESET",        "INT0",         "INT1",        "PCINT0",      "PCINT1",       "PCINT2",
    "WDT",          "TIMER2_COMPA", "TIMER2_COMPB", "TIMER2_OVF", "TIMER1_CAPT",  "TIMER1_COMPA",
    "TIMER1_COMPB", "TIMER1_OVF",   "TIMER0_COMPA", "TIMER0_COMPB", "TIMER0_OVF", "SPI_STC",
    "USART_RX",     "USART_UDRE",   "USART_TX",    "ADC",         "EE_READY",     "ANALOG_COMP",
    "TWI",          "SPM_READY"};
}  // namespace vector

/// True if bit `bit` (0..7) of a register value is set.
inline constexpr bool bit_set(uint8_t value, int bit) {
    return ((static_cast<unsigned>(value) >> static_cast<unsigned>(bit)) & 1U) != 0;
}

/// SREG bit 7: global interrupt enable.
inline constexpr int kSregI = 7;
/// Cycles of RETI (and RET) on a device with a 16-bit PC: datasheet
/// instruction set summary; simavr 1.6 charges the same (1 + 1 + 2 address bytes).
inline constexpr uint32_t kRetiCycles = 4;
/// Interrupt response time the datasheet gives for the ATmega328P (section
/// 6.7.1: PC pushed, I cleared, 4 cycles before the vector's JMP). simavr 1.6
/// charges none: the vector's first instruction runs at the cycle the
/// interrupt is taken.
inline constexpr uint32_t kDatasheetInterruptResponseCycles = 4;

/// Data-space register addresses.
namespace reg {
inline constexpr uint16_t kPinB = 0x23;
inline constexpr uint16_t kDdrB = 0x24;
inline constexpr uint16_t kPortB = 0x25;
inline constexpr uint16_t kPinC = 0x26;
inline constexpr uint16_t kDdrC = 0x27;
inline constexpr uint16_t kPortC = 0x28;
inline constexpr uint16_t kPinD = 0x29;
inline constexpr uint16_t kDdrD = 0x2A;
inline constexpr uint16_t kPortD = 0x2B;
inline constexpr uint16_t kPcifr = 0x3B;  ///< PCIF0..2 = bits 0..2
inline constexpr uint16_t kEifr = 0x3C;   ///< INTF0 = bit 0, INTF1 = bit 1
inline constexpr uint16_t kEimsk = 0x3D;  ///< INT0 = bit 0, INT1 = bit 1
inline constexpr uint16_t kMcusr = 0x54;  ///< reset flags
inline constexpr uint16_t kMcucr = 0x55;  ///< PUD = bit 4 (section 13.4.1)
inline constexpr uint16_t kEecr = 0x3F;
inline constexpr uint16_t kEedr = 0x40;
inline constexpr uint16_t kEearL = 0x41;
inline constexpr uint16_t kEearH = 0x42;
inline constexpr uint16_t kSpl = 0x5D;
inline constexpr uint16_t kSph = 0x5E;
inline constexpr uint16_t kSreg = 0x5F;
inline constexpr uint16_t kPcicr = 0x68;  ///< PCIE0..2 = bits 0..2
inline constexpr uint16_t kEicra = 0x69;  ///< ISCn1:0 = bits 2n+1:2n
inline constexpr uint16_t kPcmsk0 = 0x6B; ///< PCMSK1 = 0x6C, PCMSK2 = 0x6D
inline constexpr uint16_t kAdcsra = 0x7A;  ///< section 24.9.2 (same address on the ATmega2560)
inline constexpr uint16_t kAdmux = 0x7C;   ///< section 24.9.1 (same address on the ATmega2560)
inline constexpr uint16_t kTccr1A = 0x80;
inline constexpr uint16_t kTccr1B = 0x81;
inline constexpr uint16_t kOcr1AL = 0x88;
inline constexpr uint16_t kOcr1AH = 0x89;
inline constexpr uint16_t kOcr1BL = 0x8A;
inline constexpr uint16_t kOcr1BH = 0x8B;
inline constexpr uint16_t kTccr2A = 0xB0;
inline constexpr uint16_t kTccr2B = 0xB1;
inline constexpr uint16_t kOcr2A = 0xB3;
inline constexpr uint16_t kOcr2B = 0xB4;
inline constexpr uint16_t kTwbr = 0xB8;    ///< section 22.9.1 (same address on the ATmega2560)
inline constexpr uint16_t kTwsr = 0xB9;    ///< section 22.9.3 (same address on the ATmega2560)
inline constexpr uint16_t kTwcr = 0xBC;    ///< section 22.9.2 (same address on the ATmega2560)
inline constexpr uint16_t kUcsr0A = 0xC0;
inline constexpr uint16_t kUcsr0B = 0xC1;
inline constexpr uint16_t kUcsr0C = 0xC2;
inline constexpr uint16_t kUbrr0L = 0xC4;
inline constexpr uint16_t kUbrr0H = 0xC5;
inline constexpr uint16_t kUdr0 = 0xC6;
}  // namespace reg

/// MCUCR bit 4, PUD: 1 disables every pull-up, whatever DDxn and PORTxn say
/// (datasheet 7810D section 13.2.1, Table 13-1; the ATmega2560's MCUCR has it
/// at the same address and bit, 2549Q 13.4.1).
inline constexpr int kPud = 4;

/// ADC inputs ADC0..ADC7 (ADC6/7 only in the 32-pin packages: the Nano's A6, A7).
inline constexpr int kAdcChannels = 8;
/// The internal bandgap reference, REFS1:0 = 11 (section 24.9.1, Table 24-3).
inline constexpr double kInternalRefV = 1.1;

/// MCUSR bit: the last reset was the watchdog's.
inline constexpr uint8_t kWdrf = 1U << 3;

/// Compare-output mode bits COMnx1 in TCCRnA (non-inverting PWM when set).
namespace com_bit {
inline constexpr uint8_t kComA1 = 1U << 7;
inline constexpr uint8_t kComB1 = 1U << 5;
}  // namespace com_bit

/// Clock-select bits CSn2:0 in TCCRnB: 0 = timer stopped.
inline constexpr uint8_t kClockSelectMask = 0x07;

/// Bits of EECR (datasheet 8.6.3).
namespace eecr_bit {
inline constexpr int kEere = 0;   ///< EEPROM read enable
inline constexpr int kEepe = 1;   ///< EEPROM (programming) enable; cleared by hardware when done
inline constexpr int kEempe = 2;  ///< master programming enable, self-clearing after 4 cycles
inline constexpr int kEerie = 3;  ///< EEPROM ready interrupt enable
}  // namespace eecr_bit

/// Bits of UCSR0A / UCSR0B / UCSR0C used to time the UART.
namespace uart_bit {
inline constexpr int kU2x0 = 1;    ///< UCSR0A: double speed
inline constexpr int kUcsz02 = 2;  ///< UCSR0B: 9-bit frames
inline constexpr int kRxen0 = 4;   ///< UCSR0B: receiver enable
inline constexpr int kUcsz00 = 1;  ///< UCSR0C: character size, 2 bits
inline constexpr int kUsbs0 = 3;   ///< UCSR0C: 2 stop bits
inline constexpr int kUpm00 = 4;   ///< UCSR0C: parity mode, 2 bits (0 = none)
}  // namespace uart_bit

}  // namespace ddmr::hil::atmega328p
