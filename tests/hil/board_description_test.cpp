// Board descriptions: each board's MCU, clock, FQBN and pin numbering, and
// the pin facts derived from the MCU description (worked out from the
// ATmega328P datasheet's Figure 1-1 and the Arduino core's variants/standard).
#include "hil/board_description.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace ddmr::test {
namespace {

using hil::board_description;
using hil::BoardModel;

const hil::BoardDescription& uno() { return board_description(BoardModel::uno); }

TEST(BoardDescription, EachBoardHasItsMcuClockAndFqbn) {
    const auto& u = uno();
    EXPECT_STREQ(u.key, "uno");
    EXPECT_STREQ(u.fqbn, "arduino:avr:uno");
    EXPECT_STREQ(u.mcu->name, "atmega328p");
    EXPECT_EQ(u.clock_hz, 16'000'000u);
    const auto& nano = board_description(BoardModel::nano);
    EXPECT_STREQ(nano.fqbn, "arduino:avr:nano:cpu=atmega328");
    EXPECT_EQ(nano.clock_hz, 16'000'000u);
    EXPECT_EQ(nano.mcu, u.mcu);
    // boards.txt: pro.menu.cpu.8MHzatmega328.build.f_cpu=8000000L, build.mcu=atmega328p.
    const auto& pro = board_description(BoardModel::pro_mini_8mhz);
    EXPECT_STREQ(pro.key, "pro-mini-8mhz");
    EXPECT_STREQ(pro.fqbn, "arduino:avr:pro:cpu=8MHzatmega328");
    EXPECT_EQ(pro.clock_hz, 8'000'000u);
    EXPECT_EQ(pro.mcu, u.mcu);
}

TEST(BoardDescription, KeysParseAndEveryModelHasOne) {
    for (const BoardModel m : hil::board_models()) {
        const auto parsed = hil::parse_board_key(board_description(m).key);
        ASSERT_TRUE(parsed.has_value()) << board_description(m).key;
        EXPECT_EQ(*parsed, m);
    }
    EXPECT_FALSE(hil::parse_board_key("mega").has_value());
    EXPECT_FALSE(hil::parse_board_key("Uno").has_value());  // keys are lower case, as in the docs
    EXPECT_EQ(hil::board_key_list(), "uno, nano, pro-mini-8mhz or mega2560");
}

TEST(BoardDescription, UnoPinsMapToPortsTimersAndInterrupts) {
    const auto& b = uno();
    EXPECT_EQ(b.pin_count(), 20);
    EXPECT_EQ(hil::board_pin(b, 2)->port, 'D');
    EXPECT_EQ(hil::board_pin(b, 2)->bit, 2);
    EXPECT_EQ(*hil::board_pin(b, 2)->ext_int, 0);  // INT0 = PD2
    EXPECT_EQ(*hil::board_pin(b, 3)->ext_int, 1);  // INT1 = PD3
    EXPECT_FALSE(hil::board_pin(b, 4)->ext_int.has_value());
    EXPECT_EQ(hil::board_pin(b, 10)->port, 'B');
    EXPECT_EQ(hil::board_pin(b, 10)->bit, 2);
    EXPECT_EQ(hil::board_pin(b, 10)->ddr_register, 0x24);
    EXPECT_EQ(hil::board_pin(b, 10)->port_register, 0x25);
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 10)->oc), "OC1B");
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 9)->oc), "OC1A");
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 11)->oc), "OC2A");
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 5)->oc), "OC0B");
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 6)->oc), "OC0A");
    EXPECT_EQ(hil::oc_name(*hil::board_pin(b, 3)->oc), "OC2B");
    EXPECT_FALSE(hil::board_pin(b, 4)->oc.has_value());
    EXPECT_EQ(hil::pwm_pin_list(b), "3, 5, 6, 9, 10 and 11");
    // A4 = PC4 = PCINT12: group 1 (PCMSK1), bit 4; PINC at 0x26.
    EXPECT_EQ(hil::board_pin(b, 18)->port, 'C');
    EXPECT_EQ(*hil::board_pin(b, 18)->pcint_group, 1);
    EXPECT_EQ(hil::board_pin(b, 18)->pcint_bit, 4);
    EXPECT_EQ(hil::board_pin(b, 18)->pin_register, 0x26);
    EXPECT_EQ(*hil::board_pin(b, 8)->pcint_group, 0);  // PB0 = PCINT0
    EXPECT_EQ(*hil::board_pin(b, 7)->pcint_group, 2);  // PD7 = PCINT23
    EXPECT_EQ(hil::board_pin(b, 7)->pcint_bit, 7);
    EXPECT_FALSE(hil::board_pin(b, 20).has_value());
    EXPECT_FALSE(hil::board_pin(b, -1).has_value());
}

TEST(BoardDescription, PinNamesAsSilkscreenAndSketchesWriteThem) {
    const auto& b = uno();
    EXPECT_EQ(*hil::parse_pin_name(b, "A5"), 19);
    EXPECT_EQ(*hil::parse_pin_name(b, "a0"), 14);
    EXPECT_EQ(*hil::parse_pin_name(b, "14"), 14);
    EXPECT_EQ(*hil::parse_pin_name(b, "D7"), 7);
    EXPECT_FALSE(hil::parse_pin_name(b, "A6").has_value());  // Nano/Pro Mini: analog only; Uno: none
    EXPECT_FALSE(hil::parse_pin_name(b, "20").has_value());
    EXPECT_FALSE(hil::parse_pin_name(b, "x").has_value());
    EXPECT_FALSE(hil::parse_pin_name(b, "").has_value());
    EXPECT_FALSE(hil::parse_pin_name(b, "A").has_value());
    EXPECT_EQ(hil::pin_label(b, 5), "D5");
    EXPECT_EQ(hil::pin_label(b, 14), "A0");
    EXPECT_EQ(hil::sketch_pin_name(b, 5), "5");
    EXPECT_EQ(hil::sketch_pin_name(b, 14), "A0");
    EXPECT_EQ(hil::pin_range(b), "0..13, A0..A5");
    const auto& nano = board_description(BoardModel::nano);
    ASSERT_EQ(nano.analog_only.size(), 2u);
    EXPECT_STREQ(nano.analog_only[0], "A6");
}

/// The entries of a PROGMEM table in an Arduino variant's pins_arduino.h.
std::vector<std::string> variant_table(const std::string& variant, const std::string& table) {
    std::ifstream in("/usr/share/arduino/hardware/arduino/avr/variants/" + variant + "/pins_arduino.h");
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    const auto at = s.find(table + "[] = {");
    if (at == std::string::npos) return {};
    const auto open = s.find('{', at) + 1;  // the entries, not the table's name ("..._PGM")
    s = s.substr(open, s.find("};", open) - open);
    s = std::regex_replace(s, std::regex("//[^\n]*|/\\*[^*]*\\*/"), "");
    // The ATmega8's entries (#if defined(__AVR_ATmega8__) ... #else): not these boards'.
    s = std::regex_replace(s, std::regex("#if defined\\(__AVR_ATmega8__\\)[^#]*#else|#endif"), "");
    std::vector<std::string> out;
    const std::regex entry("\\b(P[A-L]|_BV\\( *[0-7] *\\)|NOT_ON_TIMER|TIMER[0-5][ABC]?)");
    for (auto it = std::sregex_iterator(s.begin(), s.end(), entry); it != std::sregex_iterator(); ++it) {
        const std::string e = it->str();
        out.push_back(e.rfind("_BV", 0) == 0 ? std::string(1, e[e.find_first_of("01234567")]) : e);
    }
    return out;
}

/// Each board's pin table against the Arduino AVR core's variant (Debian's
/// arduino-core-avr): port, bit and timer output of every digital pin.
void expect_variant(const hil::BoardDescription& b, const std::string& variant) {
    const auto ports = variant_table(variant, "digital_pin_to_port_PGM");
    const auto bits = variant_table(variant, "digital_pin_to_bit_mask_PGM");
    const auto timers = variant_table(variant, "digital_pin_to_timer_PGM");
    ASSERT_EQ(ports.size(), static_cast<std::size_t>(b.pin_count())) << variant;
    ASSERT_EQ(bits.size(), ports.size());
    ASSERT_EQ(timers.size(), ports.size());
    for (int n = 0; n < b.pin_count(); ++n) {
        const auto i = static_cast<std::size_t>(n);
        const auto pin = hil::board_pin(b, n);
        ASSERT_TRUE(pin.has_value()) << n;
        EXPECT_EQ(std::string(1, pin->port), ports[i].substr(1)) << b.key << " pin " << n;
        EXPECT_EQ(std::to_string(pin->bit), bits[i]) << b.key << " pin " << n;
        // The core's TIMER0A, TIMER1B, ...: the OCnx unit analogWrite uses.
        const std::string want = timers[i] == "NOT_ON_TIMER" ? "-" : "OC" + timers[i].substr(5);
        EXPECT_EQ(pin->oc ? hil::oc_name(*pin->oc) : "-", want) << b.key << " pin " << n;
    }
}

TEST(BoardDescription, PinTablesAreTheArduinoCoresVariants) {
    expect_variant(uno(), "standard");
    expect_variant(board_description(BoardModel::mega2560), "mega");
}

TEST(BoardDescription, MegaPinsInterruptsAndUsarts) {
    const auto& m = board_description(BoardModel::mega2560);
    EXPECT_STREQ(m.mcu->name, "atmega2560");
    EXPECT_STREQ(m.fqbn, "arduino:avr:mega:cpu=atmega2560");
    EXPECT_EQ(m.pin_count(), 70);
    EXPECT_EQ(hil::pin_range(m), "0..53, A0..A15");
    EXPECT_EQ(*hil::parse_pin_name(m, "A15"), 69);
    // External interrupts by the datasheet's INTn (attachInterrupt(0) is INT4 on pin 2).
    EXPECT_EQ(*hil::board_pin(m, 2)->ext_int, 4);   // PE4
    EXPECT_EQ(*hil::board_pin(m, 3)->ext_int, 5);   // PE5
    EXPECT_EQ(*hil::board_pin(m, 18)->ext_int, 3);  // PD3
    EXPECT_EQ(*hil::board_pin(m, 21)->ext_int, 0);  // PD0
    EXPECT_FALSE(hil::board_pin(m, 2)->pcint_group.has_value());  // PE4 has no pin-change interrupt
    EXPECT_EQ(*hil::board_pin(m, 53)->pcint_group, 0);            // PB0 = PCINT0
    EXPECT_EQ(*hil::board_pin(m, 15)->pcint_group, 1);            // PJ0 = PCINT9
    EXPECT_EQ(hil::board_pin(m, 15)->pcint_bit, 1);
    EXPECT_EQ(*hil::board_pin(m, 0)->pcint_group, 1);             // PE0 = PCINT8
    EXPECT_EQ(hil::board_pin(m, 0)->pcint_bit, 0);
    EXPECT_EQ(*hil::board_pin(m, 62)->pcint_group, 2);            // A8 = PK0 = PCINT16
    EXPECT_EQ(hil::board_pin(m, 6)->pin_register, 0x100);         // PINH: extended I/O
    EXPECT_EQ(hil::pwm_pin_list(m), "2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 44, 45 and 46");
    // Serial1 (USART1) on D19 (RXD1 = PD2) and D18 (TXD1 = PD3).
    EXPECT_EQ(hil::pin_number_of(m, m.mcu->usarts[1].rxd), 19);
    EXPECT_EQ(hil::pin_number_of(m, m.mcu->usarts[1].txd), 18);
}

TEST(BoardDescription, TheConsoleUsartIsOnPinsZeroAndOne) {
    for (const BoardModel m : hil::board_models()) {
        const auto& b = board_description(m);
        EXPECT_EQ(hil::pin_number_of(b, b.console().rxd), 0) << b.key;
        EXPECT_EQ(hil::pin_number_of(b, b.console().txd), 1) << b.key;
        EXPECT_EQ(hil::usart_irq_name(b.console()), '0') << b.key;
    }
}

TEST(BoardDescription, SerialPortsAreTheMcusUsartsByArduinoName) {
    const auto& uno = board_description(BoardModel::uno);
    EXPECT_EQ(hil::parse_serial_port(uno, "Serial"), 0);
    EXPECT_FALSE(hil::parse_serial_port(uno, "Serial1"));  // the ATmega328P has USART0 only
    EXPECT_FALSE(hil::parse_serial_port(uno, "serial"));
    EXPECT_EQ(hil::serial_port_list(uno), "Serial");
    const auto& mega = board_description(BoardModel::mega2560);
    EXPECT_EQ(hil::parse_serial_port(mega, "Serial1"), 1);
    EXPECT_EQ(hil::parse_serial_port(mega, "Serial3"), 3);
    EXPECT_FALSE(hil::parse_serial_port(mega, "Serial4"));
    EXPECT_FALSE(hil::parse_serial_port(mega, "Serial0"));
    EXPECT_EQ(hil::serial_port_list(mega), "Serial, Serial1, Serial2 or Serial3");
    EXPECT_EQ(hil::usart_irq_name(mega.mcu->usarts[2]), '2');
}

}  // namespace
}  // namespace ddmr::test
