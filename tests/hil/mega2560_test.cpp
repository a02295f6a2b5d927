// The Arduino Mega 2560 (ATmega2560) end to end, with the Mega example
// (firmware/examples/mega_l298n_int45, built for arduino:avr:mega:cpu=atmega2560):
// Timer3/Timer4 PWM on its pins, INT4/INT5 encoders, the 4 KiB EEPROM, and
// the ELF check. Numbers from the ATmega2560 datasheet (2549Q) and the
// Arduino core's init() (Timers 1..5: phase correct 8-bit, clock/64).
#include <gtest/gtest.h>

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <avr_ioport.h>
#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include "hil/board.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/pin_waveforms.hpp"
#include "hil/robot_rig.hpp"
#include "support/example_rig.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

hil::RigConfig mega_rig() { return example_rig("mega_l298n_int45"); }

hil::ElfImage mega_elf() { return hil::ElfImage::read(test_firmware_dir() / "mega_l298n_int45.elf"); }

bool run_to_text(hil::RobotRig& rig, const std::string& text, double seconds) {
    auto& core = rig.core();
    const hil::Cycles limit = core.cycle() + hil::s_to_cycles(seconds, core.clock_hz());
    return core.run_until(limit, [&] { return rig.uart().text().find(text) != std::string::npos; }) ==
           hil::RunStop::kCondition;
}

TEST(Mega2560, TheElfIsTheBoardsAndNotTheUnos) {
    const hil::ElfImage elf = mega_elf();
    EXPECT_NO_THROW(elf.require_mcu(hil::atmega2560_mcu(), "mega2560"));
    try {
        elf.require_mcu(hil::atmega328p_mcu(), "uno");
        FAIL() << "a Mega ELF passed as the Uno's";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("avr6"), std::string::npos) << e.what();
    }
}

TEST(Mega2560, Timer3AndTimer4PwmOnPins5And6) {
    const hil::ElfImage elf = mega_elf();
    hil::RobotRig rig(elf, mega_rig());
    EXPECT_STREQ(rig.core().mcu().name, "atmega2560");
    ASSERT_TRUE(run_to_text(rig, "forward\r\n", 1.0));
    // analogWrite(180) on OC3A (D5, PE3) and OC4A (D6, PH3): phase correct,
    // TOP 255, clock/64: a period of 2 x 255 x 64 = 32,640 cycles (490.2 Hz at
    // 16 MHz), high for 180/255 of it.
    for (const int pin : {5, 6}) {
        const hil::TimerOutputDecoder* t = rig.driver().pins().timer_of(pin);
        ASSERT_NE(t, nullptr) << pin;
        EXPECT_EQ(t->period_cycles(0), 32'640u) << pin;
        EXPECT_NEAR(rig.driver().pins().duty(pin), 180.0 / 255.0, 1e-9) << pin;
    }
    EXPECT_EQ(hil::board_pin(rig.core().board(), 5)->oc->timer, 3);
    EXPECT_EQ(hil::board_pin(rig.core().board(), 6)->oc->timer, 4);
}

TEST(Mega2560, EncoderEdgesOnInt4EnterTheirIsr) {
    const hil::ElfImage elf = mega_elf();
    hil::RobotRig rig(elf, mega_rig());
    std::vector<hil::Cycles> edges;  // left encoder: D2 = PE4 = INT4 (vector 5)
    rig.encoders().set_edge_listener([&](int pin, hil::Cycles c, bool) {
        if (pin == 2) edges.push_back(c);
    });
    EXPECT_EQ(rig.encoders().vector_of(1), 5);  // wheels: [0] right (D3, INT5), [1] left (D2, INT4)
    EXPECT_EQ(rig.encoders().vector_of(0), 6);
    ASSERT_TRUE(run_to_text(rig, "done", 3.0));
    const std::vector<hil::Cycles>& entries = rig.encoders().isr_entries(1);
    ASSERT_GT(edges.size(), 700u);
    ASSERT_EQ(entries.size(), edges.size());  // CHANGE: every edge, none lost
    // Each edge enters INT4's vector after at most the longest other ISR and
    // an instruction (simavr charges no response cycles: 0 when nothing is
    // running); most enter at once.
    std::size_t immediate = 0;
    for (std::size_t i = 0; i < edges.size(); ++i) {
        ASSERT_GE(entries[i], edges[i]) << i;
        EXPECT_LE(entries[i] - edges[i], 150u) << i;
        if (entries[i] - edges[i] <= 4) ++immediate;
    }
    EXPECT_GT(immediate, edges.size() / 2);
    EXPECT_EQ(rig.encoders().stats(1).lost_edges, 0u);
}

TEST(Mega2560, TheFourKibEepromDumpsWhole) {
    const hil::ElfImage elf = mega_elf();
    hil::RobotRig rig(elf, mega_rig());
    ASSERT_TRUE(run_to_text(rig, "done", 3.0));
    const hil::EepromImage image = rig.eeprom().read_all();
    ASSERT_EQ(image.size(), 4096u);
    // The sketch keeps the counts in bytes 4092..4095 (little-endian 16 bits).
    const auto left = rig.variables().read_as<int32_t>("leftTicks");
    const auto right = rig.variables().read_as<int32_t>("rightTicks");
    EXPECT_EQ(image[4092] | (image[4093] << 8), left);
    EXPECT_EQ(image[4094] | (image[4095] << 8), right);
    EXPECT_EQ(image[0], 0xFF);  // the rest erased
    EXPECT_THROW(rig.eeprom().preload(hil::EepromPort::erased(hil::atmega328p_mcu())), std::invalid_argument);
}

// Pin-change groups 1 and 2, which simavr 1.6's ATmega2560 core lacks, work
// as the datasheet says (2549Q 15.2.5..15.2.8): each change of a masked pin
// enters the group's vector once; an unmasked pin of the group does nothing.
TEST(Mega2560, PinChangeGroupsOneAndTwoAreRestored) {
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "pcint_mega_fixture.elf");
    elf.require_mcu(hil::atmega2560_mcu(), "mega2560");
    hil::AvrCoreConfig config;
    config.board = hil::BoardModel::mega2560;
    hil::AvrCore core(elf, config);
    EXPECT_EQ(core.restored_pin_change_groups(), (std::vector<int>{1, 2}));
    const hil::FirmwareVariables vars(elf, core);
    core.run_until(2000);  // main() has set the masks and SEI
    const auto toggle = [&](char port, uint8_t bit, int times) {
        avr_irq_t* pin = avr_io_getirq(core.raw(), static_cast<uint32_t>(AVR_IOCTL_IOPORT_GETIRQ(port)), bit);
        ASSERT_NE(pin, nullptr);
        for (int i = 0; i < times; ++i) {
            avr_raise_irq(pin, pin->value != 0 ? 0 : 1);
            core.run_until(core.cycle() + 200);
        }
    };
    toggle('K', 0, 6);  // PCINT16: 6 changes
    toggle('K', 1, 4);  // PCINT17: masked off
    toggle('J', 0, 5);  // PCINT9
    toggle('B', 0, 3);  // PCINT0: simavr's own
    EXPECT_EQ(vars.read_as<uint16_t>("pcint2_count"), 6);
    EXPECT_EQ(vars.read_as<uint16_t>("pcint1_count"), 5);
    EXPECT_EQ(vars.read_as<uint16_t>("pcint0_count"), 3);
}

hil::RigConfig thesis_wiring_on_mega(std::optional<int> host_usart) {
    hil::RigConfig c;
    c.board.model = hil::BoardModel::mega2560;  // the thesis robot's pins exist on the Mega
    c.host_usart = host_usart;
    return c;
}

// The host's adapter on Serial1: what it sends reaches USART1's receiver, what
// USART1 transmits is what the link receives (USART0's text is not), and the
// frame time is USART1's: UBRR1 = 103 with U2X1, (103 + 1) x 8 = 832 cycles a bit.
TEST(Mega2560, TheHostAdapterOnSerial1TalksToUsart1) {
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "serial1_mega_fixture.elf");
    hil::RobotRig rig(elf, thesis_wiring_on_mega(1));
    EXPECT_EQ(rig.uart().usart().index, 1);
    rig.uart().send("bt ok");
    ASSERT_TRUE(run_to_text(rig, "BT OK", 0.05)) << rig.uart().text();
    EXPECT_EQ(rig.uart().text(), "BT OK");
    EXPECT_EQ(rig.uart().cycles_per_bit(), 832U);
    EXPECT_EQ(rig.uart().cycles_per_byte(), 8320U);  // 8N1: 10 bits
}

TEST(Mega2560, TheHostAdapterIsOnSerialByDefault) {
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "serial1_mega_fixture.elf");
    hil::RobotRig rig(elf, thesis_wiring_on_mega(std::nullopt));
    EXPECT_EQ(rig.uart().usart().index, 0);
    ASSERT_TRUE(run_to_text(rig, "usart0\r\n", 0.05)) << rig.uart().text();
    EXPECT_EQ(rig.uart().cycles_per_bit(), 1664U);  // UBRR0 = 207, U2X0
}

TEST(Mega2560, AHostSerialPortTheBoardLacksOrTheWiringUsesIsRefused) {
    hil::RigConfig uno;
    uno.host_usart = 1;
    try {
        hil::RobotRig rig(hil::ElfImage::read(firmware_elf()), uno);
        FAIL() << "Serial1 accepted on the Uno";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("Serial1 does not exist on the Arduino Uno"), std::string::npos)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("its serial ports are Serial"), std::string::npos) << e.what();
    }
    hil::RigConfig mega = thesis_wiring_on_mega(1);
    mega.board.wheel[1].encoder.pin[0] = 19;  // RXD1
    try {
        hil::RobotRig rig(hil::ElfImage::read(test_firmware_dir() / "serial1_mega_fixture.elf"), mega);
        FAIL() << "an encoder on RXD1 accepted with the adapter on Serial1";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("key 'wheels.left.encoder.OUT': pin 19 carries Serial1's RX"),
                  std::string::npos)
            << e.what();
    }
}

// Channel C of Timers 3, 4 and 5 on the board's pins 3 (PE5), 8 (PH5) and 44
// (PL5): phase correct 8-bit at clock/64, a period of 2 x 255 x 64 = 32,640
// cycles, high for OCR/255 of it (pwm_c_mega_fixture.c).
TEST(Mega2560, ChannelCPwmOnPins3And8And44) {
    const hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "pwm_c_mega_fixture.elf");
    hil::AvrCoreConfig config;
    config.board = hil::BoardModel::mega2560;
    hil::AvrCore core(elf, config);
    hil::PinWaveforms pins(core, {3, 8, 44});
    core.run_until(100'000);
    pins.advance_to(core.cycle());
    for (const auto& [pin, ocr] : {std::pair{3, 64}, std::pair{8, 128}, std::pair{44, 192}}) {
        ASSERT_TRUE(pins.timer_driven(pin)) << pin;
        EXPECT_NEAR(pins.duty(pin), ocr / 255.0, 1e-9) << pin;
        // Two rising edges apart: one period; the high part between.
        hil::Cycles t = core.cycle();
        while (!pins.level_at(pin, t)) t = pins.next_change_after(pin, t);
        t = pins.next_change_after(pin, t);  // falling
        const hil::Cycles rise = pins.next_change_after(pin, t);
        const hil::Cycles fall = pins.next_change_after(pin, rise);
        const hil::Cycles next_rise = pins.next_change_after(pin, fall);
        EXPECT_EQ(next_rise - rise, 32'640u) << pin;
        EXPECT_EQ(fall - rise, static_cast<hil::Cycles>(ocr) * 2 * 64) << pin;
    }
}

TEST(Mega2560, TheUnoNeedsNoRestoredGroups) {
    const hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    EXPECT_TRUE(core.restored_pin_change_groups().empty());
}

}  // namespace
}  // namespace ddmr::test
