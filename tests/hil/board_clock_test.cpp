// The board's clock reaches every part that counts time: the Pro Mini
// example (firmware/examples/pro_mini_8mhz_tb6612, built for
// arduino:avr:pro:cpu=8MHzatmega328) on its board, with numbers from the
// ATmega328P datasheet (7810D) and the Arduino core worked out by hand.
#include <gtest/gtest.h>

#include <string>

#include "hil/board.hpp"
#include "hil/robot_rig.hpp"
#include "support/example_rig.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

hil::RigConfig pro_mini_rig() { return example_rig("pro_mini_8mhz_tb6612"); }

hil::ElfImage pro_mini_elf() { return hil::ElfImage::read(test_firmware_dir() / "pro_mini_8mhz_tb6612.elf"); }

TEST(BoardClock, TheRigRunsTheBoardsMcuAtItsClock) {
    const hil::ElfImage elf = pro_mini_elf();
    hil::RobotRig rig(elf, pro_mini_rig());
    EXPECT_EQ(rig.core().clock_hz(), 8'000'000u);
    EXPECT_STREQ(rig.core().board().key, "pro-mini-8mhz");
    EXPECT_STREQ(rig.core().mcu().name, "atmega328p");
    rig.core().run_until(4'000'000);
    EXPECT_DOUBLE_EQ(rig.core().seconds(), 0.5);  // 4e6 cycles at 8 MHz
    // Coupling step and truth period: 62.5 us and 1 ms at 8 MHz.
    EXPECT_EQ(rig.coupler().config().step_cycles, 500u);
    EXPECT_EQ(rig.coupler().config().truth_period_cycles, 8000u);
}

TEST(BoardClock, AUartFrameAt8MHzIsTenBitsOfUbrrPlusOneTimesEight) {
    // Serial.begin(38400) at F_CPU = 8 MHz: U2X0 = 1, UBRR0 = (8e6 / 4 / 38400
    // - 1) / 2 = 25 (integer division), a bit is (25 + 1) x 8 = 208 cycles,
    // an 8N1 frame 2080 cycles = 260 us (38462 baud).
    const hil::ElfImage elf = pro_mini_elf();
    hil::RobotRig rig(elf, pro_mini_rig());
    rig.core().run_until(800'000);  // 0.1 s: setup() has printed its first line
    EXPECT_EQ(rig.core().data(rig.core().mcu().usarts[0].ubrrl), 25);
    EXPECT_EQ(rig.uart().cycles_per_bit(), 208u);
    EXPECT_EQ(rig.uart().cycles_per_byte(), 2080u);
    const auto& bytes = rig.uart().received();
    ASSERT_GE(bytes.size(), 28u);
    EXPECT_EQ(rig.uart().text().substr(0, 28), "pro_mini_8mhz_tb6612 ready\r\n");
    // Serial's buffer holds the line: bytes leave back to back, one frame
    // apart on average (single UDR0 writes jitter by the TX ISR's timing:
    // the data register is double-buffered).
    const double mean_gap = static_cast<double>(bytes[27].cycle - bytes[3].cycle) / 24.0;
    EXPECT_NEAR(mean_gap, 2080.0, 2080.0 * 0.002);
}

TEST(BoardClock, MillisAndThePwmPeriodFollowTheClock) {
    const hil::ElfImage elf = pro_mini_elf();
    hil::RobotRig rig(elf, pro_mini_rig());
    auto& core = rig.core();
    // The sketch prints "forward" right after analogWrite(200) and then waits
    // for millis() to pass 1500: 1.5 s of simulated time, 12e6 cycles.
    ASSERT_EQ(core.run_until(2 * 8'000'000, [&] { return rig.uart().text().find("forward\r\n") != std::string::npos; }),
              hil::RunStop::kCondition);
    const hil::Cycles forward = core.cycle();
    // Timer1 phase correct, TOP 255, prescaler 64: 2 x 255 x 64 = 32,640
    // cycles a period (245 Hz at 8 MHz, 490 Hz at 16 MHz), duty 200/255.
    const hil::TimerOutputDecoder* t1 = rig.driver().pins().timer_of(9);
    ASSERT_NE(t1, nullptr);
    EXPECT_EQ(t1->period_cycles(0), 32'640u);
    EXPECT_NEAR(rig.driver().pins().duty(9), 200.0 / 255.0, 1e-9);
    ASSERT_EQ(core.run_until(forward + 3 * 8'000'000,
                             [&] { return rig.uart().text().find("stop after") != std::string::npos; }),
              hil::RunStop::kCondition);
    const double driven_s = hil::cycles_to_s(core.cycle() - forward, core.clock_hz());
    EXPECT_GT(driven_s, 1.49);
    EXPECT_LT(driven_s, 1.52);
}

}  // namespace
}  // namespace ddmr::test
