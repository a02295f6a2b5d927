// The ATmega328P's description against its datasheet (7810D): memory map,
// Table 12-6 vectors, section 13.3 alternate port functions, the USART0
// registers.
#include "hil/mcu.hpp"

#include <gtest/gtest.h>

namespace ddmr::test {
namespace {

TEST(Mcu, Atmega328pMemoryAndVectors) {
    const hil::McuDescription& m = hil::atmega328p_mcu();
    EXPECT_STREQ(m.name, "atmega328p");
    EXPECT_EQ(m.elf_arch, 5u);
    EXPECT_EQ(m.flash_bytes, 32u * 1024);
    EXPECT_EQ(m.sram_bytes, 2048u);
    EXPECT_EQ(m.sram_start, 0x100);
    EXPECT_EQ(m.ram_end, 0x8FF);  // 0x100 + 2048 - 1
    EXPECT_EQ(m.eeprom_bytes, 1024u);
    EXPECT_EQ(m.vector_count(), 26);
    EXPECT_EQ(m.vector_name(0), "RESET");
    EXPECT_EQ(m.vector_name(m.int0_vector), "INT0");
    EXPECT_EQ(m.vector_name(m.int0_vector + 1), "INT1");
    EXPECT_EQ(m.vector_name(m.pcint0_vector + 2), "PCINT2");
    EXPECT_EQ(m.vector_name(18), "USART_RX");
    EXPECT_EQ(m.vector_name(26), "vector 26");
    EXPECT_EQ(m.reti_cycles, 4u);  // 16-bit PC
}

TEST(Mcu, Atmega328pInterruptPinsAndSenseRegisters) {
    const hil::McuDescription& m = hil::atmega328p_mcu();
    EXPECT_EQ(*m.ext_int_at({'D', 2}), 0);
    EXPECT_EQ(*m.ext_int_at({'D', 3}), 1);
    EXPECT_FALSE(m.ext_int_at({'D', 4}).has_value());
    EXPECT_EQ(m.eicr_of(1), 0x69);  // EICRA holds ISC11:10 in bits 3:2
    EXPECT_EQ(hil::McuDescription::isc_shift(1), 2u);
    EXPECT_EQ(*m.pcint_at({'B', 0}), 0);
    EXPECT_EQ(*m.pcint_at({'C', 6}), 14);  // PC6 = RESET = PCINT14
    EXPECT_EQ(*m.pcint_at({'D', 0}), 16);
    EXPECT_FALSE(m.pcint_at({'E', 0}).has_value());
    EXPECT_EQ(m.pcmsk0, 0x6B);
    EXPECT_EQ(m.pcicr, 0x68);
}

TEST(Mcu, Atmega328pTimersPortsAndUsart) {
    const hil::McuDescription& m = hil::atmega328p_mcu();
    ASSERT_EQ(m.timers.size(), 3u);
    EXPECT_EQ(m.timers[1].bits, 16);
    EXPECT_EQ(m.oc_at({'B', 1})->timer, 1);    // OC1A = PB1
    EXPECT_EQ(m.oc_at({'D', 3})->channel, 1);  // OC2B = PD3
    EXPECT_FALSE(m.oc_at({'D', 4}).has_value());
    ASSERT_NE(m.port('B'), nullptr);
    EXPECT_EQ(m.port('B')->pin, 0x23);
    EXPECT_EQ(m.port('D')->ddr, 0x2A);
    EXPECT_EQ(m.port('A'), nullptr);
    ASSERT_EQ(m.usarts.size(), 1u);
    EXPECT_EQ(m.usarts[0].udr, 0xC6);
    EXPECT_EQ(m.usarts[0].ubrrl, 0xC4);
    EXPECT_EQ(m.vector_name(m.usarts[0].udre_vector), "USART_UDRE");
}

}  // namespace
}  // namespace ddmr::test
