// Board descriptions: each board's MCU, clock, FQBN and pin numbering, and
// the pin facts derived from the MCU description (worked out from the
// ATmega328P datasheet's Figure 1-1 and the Arduino core's variants/standard).
#include "hil/board_description.hpp"

#include <gtest/gtest.h>

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
    EXPECT_EQ(hil::board_key_list(), "uno, nano or pro-mini-8mhz");
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

TEST(BoardDescription, TheConsoleUsartIsOnPinsZeroAndOne) {
    for (const BoardModel m : hil::board_models()) {
        const auto& b = board_description(m);
        EXPECT_EQ(hil::pin_number_of(b, b.console().rxd), 0) << b.key;
        EXPECT_EQ(hil::pin_number_of(b, b.console().txd), 1) << b.key;
        EXPECT_EQ(hil::console_uart_name(b), '0') << b.key;
    }
}

}  // namespace
}  // namespace ddmr::test
