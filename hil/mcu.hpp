#pragma once
// McuDescription: one AVR part's facts as data, read by every part of the
// HIL that depends on the chip: memory sizes and the ELF architecture (the
// ELF check, the profilers, the race detector), the interrupt vector table
// (names, INTn and PCINT vectors, the USART vectors), the I/O ports, which
// pin carries which INTn / PCINTn / OCnx / RXDn / TXDn, the timers
// (avr_timers.hpp) and the USARTs. A new chip is a new description; no part
// asks which chip it runs on.
//
// The ATmega328P's description (Uno, Nano, Pro Mini) is built from
// hil/atmega328p.hpp, whose named constants cite the datasheet.
// Addresses are data-space addresses (I/O address + 0x20), as simavr uses.

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hil/avr_timers.hpp"

namespace ddmr::hil {

/// The most interrupt vectors of a supported MCU (the ATmega2560 has 57):
/// a set of vectors fits one 64-bit mask (bit v = vector v).
inline constexpr int kMaxVectors = 64;
using VectorMask = uint64_t;
/// The largest EEPROM of a supported MCU (the ATmega2560's 4 KiB): what a
/// sketch contract may address before the board is known.
inline constexpr uint32_t kMaxEepromBytes = 4096;

/// An I/O port's three registers: PINx (input levels), DDRx (1 = output),
/// PORTx (output level, or the pull-up of an input).
struct PortRegisters {
    char port = 'B';
    uint16_t pin = 0;
    uint16_t ddr = 0;
    uint16_t port_register = 0;
};

/// One USART: its registers, vectors and pins (datasheet "USART" chapter).
struct UsartDesc {
    int index = 0;  ///< n in UCSRnA, Serial (0), Serial1 (1), ...
    uint16_t ucsra = 0, ucsrb = 0, ucsrc = 0, ubrrl = 0, ubrrh = 0, udr = 0;
    int rx_vector = 0, udre_vector = 0, tx_vector = 0;
    PortBit rxd{}, txd{};
};

/// The output-compare unit a pin carries: timer n, channel 0 = A, 1 = B.
struct OcChannel {
    int timer = 0;
    int channel = 0;
};

/// What REFS1:0 in ADMUX select as the ADC's reference.
enum class AdcRefKind : uint8_t { aref, avcc, internal, reserved };
struct AdcRefChoice {
    AdcRefKind kind = AdcRefKind::reserved;
    double internal_v = 0.0;  ///< the internal reference [V] (kind internal)
};

/// The ADC (datasheet chapter "Analog-to-Digital Converter"): its registers
/// (data-space addresses), single-ended inputs ADC0..ADC(channels - 1) on the
/// analog pins A0.., and the reference each REFS1:0 value selects.
struct AdcDesc {
    uint16_t admux = 0;   ///< REFS1:0 = bits 7:6, ADLAR = 5, MUX = 4:0
    uint16_t adcsra = 0;  ///< ADEN = 7, ADSC = 6, ADPS2:0 = 2:0
    int channels = 0;
    std::array<AdcRefChoice, 4> refs{};  ///< indexed by REFS1:0
};

struct McuDescription {
    const char* name = "";   ///< avr-gcc -mmcu and simavr core name: "atmega328p"
    const char* label = "";  ///< as the datasheet writes it: "ATmega328P"
    unsigned elf_arch = 0;   ///< e_flags architecture (EF_AVR_ARCH_AVR5 = 5, AVR6 = 6)
    uint32_t flash_bytes = 0;
    uint32_t sram_bytes = 0;
    uint16_t sram_start = 0;  ///< first SRAM address (after the I/O space)
    uint16_t ram_end = 0;     ///< last SRAM address (RAMEND)
    uint32_t eeprom_bytes = 0;
    int vector_bytes = 4;                   ///< each vector is a JMP (2 words)
    std::vector<const char*> vector_names;  ///< avr-libc's <NAME>_vect without _vect; [0] = RESET
    /// Bytes of a return address on the stack: 2 with a 16-bit PC, 3 with a 22-bit PC.
    uint16_t pc_bytes = 2;
    /// Cycles of RETI/RET: 4 with a 16-bit PC, 5 with a 22-bit PC (instruction set summary).
    uint32_t reti_cycles = 4;

    // Core registers.
    uint16_t spl = 0, sph = 0, sreg = 0, mcusr = 0;
    uint16_t mcucr = 0;  ///< MCUCR: PUD (bit pud_bit) disables all pull-ups
    uint16_t twsr = 0;   ///< TWSR: the TWI status (bits 7:3) and prescaler (1:0)
    uint16_t twcr = 0;   ///< TWCR: TWINT = bit 7
    uint16_t twbr = 0;   ///< TWBR: the bit rate register
    PortBit twi_sda{}, twi_scl{};  ///< the TWI's pins
    int pud_bit = 0;
    uint16_t eecr = 0, eedr = 0, eearl = 0, eearh = 0;

    std::vector<PortRegisters> ports;

    /// External interrupts: ext_int_pins[n] carries INTn; INTn's vector is
    /// int0_vector + n; its sense bits ISCn1:0 are bits 2(n%4)+1:2(n%4) of
    /// eicr[n/4] (EICRA for INT0-3, EICRB for INT4-7).
    std::vector<PortBit> ext_int_pins;
    int int0_vector = 0;
    std::vector<uint16_t> eicr;
    uint16_t eimsk = 0, eifr = 0;

    /// Pin-change interrupts: pcint_pins[k] carries PCINTk (nullopt: no such
    /// PCINT); group k/8 has enable bit PCIE(k/8) in PCICR, flag PCIF(k/8) in
    /// PCIFR, mask register pcmsk0 + k/8 (bit k%8), vector pcint0_vector + k/8.
    std::vector<std::optional<PortBit>> pcint_pins;
    int pcint0_vector = 0;
    uint16_t pcicr = 0, pcifr = 0, pcmsk0 = 0;

    std::vector<TimerDesc> timers;  ///< indexed by n
    std::vector<UsartDesc> usarts;  ///< indexed by n
    AdcDesc adc;

    [[nodiscard]] int vector_count() const { return static_cast<int>(vector_names.size()); }
    /// The vector's name, or "vector N" past the table.
    [[nodiscard]] std::string vector_name(int vector) const;
    /// The port's registers, or nullptr if the chip has no such port.
    [[nodiscard]] const PortRegisters* port(char letter) const;
    /// n of the INTn on that pin, if any.
    [[nodiscard]] std::optional<int> ext_int_at(PortBit pin) const;
    /// k of the PCINTk on that pin, if any.
    [[nodiscard]] std::optional<int> pcint_at(PortBit pin) const;
    /// The OCnx unit on that pin, if any.
    [[nodiscard]] std::optional<OcChannel> oc_at(PortBit pin) const;
    /// The address of INTn's sense register (EICRA or EICRB) and the shift of ISCn0 in it.
    [[nodiscard]] uint16_t eicr_of(int n) const { return eicr[static_cast<std::size_t>(n / 4)]; }
    [[nodiscard]] static unsigned isc_shift(int n) { return 2U * static_cast<unsigned>(n % 4); }
};

/// A megaAVR USART at `ucsra` (UCSRnA; B, C, UBRRnL, UBRRnH, UDRn at +1, +2,
/// +4, +5, +6) with its RX, UDRE, TX vectors at rx_vector, +1, +2.
UsartDesc megaavr_usart(int index, uint16_t ucsra, int rx_vector, PortBit rxd, PortBit txd);
/// SPL, SPH, SREG, MCUSR, MCUCR, TWSR, TWCR and the EEPROM registers: the same data addresses on
/// the ATmega328P and the ATmega2560 (both register summaries).
void set_megaavr_core_registers(McuDescription& d);

/// The ATmega328P (Uno, Nano, Pro Mini): datasheet 7810D.
const McuDescription& atmega328p_mcu();
/// The ATmega2560 (Mega 2560): datasheet 2549Q.
const McuDescription& atmega2560_mcu();

/// "OC1B".
std::string oc_name(const OcChannel& oc);

}  // namespace ddmr::hil
