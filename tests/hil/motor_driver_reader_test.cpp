// MotorDriverReader: the bridge drive decoded from Timer1/Timer2 and PORTB,
// checked against the datasheet's phase-correct waveform and against what
// the reference firmware writes.
#include "hil/motor_driver_reader.hpp"

#include <gtest/gtest.h>

#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include "hil/atmega328p.hpp"
#include "hil/uart_link.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using hil::BridgeDrive;

BridgeDrive pwm(uint16_t ocr) {
    BridgeDrive d;
    d.pwm_connected = true;
    d.timer_running = true;
    d.ocr = ocr;
    return d;
}

/// High cycles over one 32,640-cycle period, by walking the edges.
hil::Cycles high_cycles_per_period(const BridgeDrive& d) {
    hil::Cycles high = 0;
    hil::Cycles t = 0;
    while (t < 32640) {
        const hil::Cycles next = std::min<hil::Cycles>(d.next_enable_edge_after(t), 32640);
        if (d.enable_level_at(t)) high += next - t;
        t = next;
    }
    return high;
}

TEST(BridgeDrive, WaveformIsHighForTwiceOcrTimes64CyclesPerPeriod) {
    // Phase-correct: high while TCNT < OCR, counting 0..255..0 at 64 cycles per
    // count: 2 x OCR x 64 cycles high. OCR 50 -> 6400 of 32,640 (19.6 %).
    EXPECT_EQ(high_cycles_per_period(pwm(50)), 6400u);
    EXPECT_EQ(high_cycles_per_period(pwm(234)), 2u * 234u * 64u);
    EXPECT_DOUBLE_EQ(pwm(50).duty(), 50.0 / 255.0);
    EXPECT_EQ(pwm(0).next_enable_edge_after(0), BridgeDrive::kNoEdge);
    EXPECT_FALSE(pwm(0).enable_level_at(100));
    EXPECT_TRUE(pwm(255).enable_level_at(100));  // OCR = TOP: continuously high
    EXPECT_DOUBLE_EQ(pwm(255).duty(), 1.0);
}

TEST(BridgeDrive, OcrAboveTopKeepsTheLatchedLevel) {
    // analogWrite(10, -30) stores 65506 in OCR1B: never equal to the 8-bit count.
    BridgeDrive d = pwm(65506);
    d.latch_high = false;
    EXPECT_DOUBLE_EQ(d.duty(), 0.0);
    EXPECT_EQ(d.next_enable_edge_after(0), BridgeDrive::kNoEdge);
    d.latch_high = true;
    EXPECT_DOUBLE_EQ(d.duty(), 1.0);
}

TEST(BridgeDrive, PortLevelWhenPwmIsDisconnected) {
    BridgeDrive d;
    d.port_level = true;  // digitalWrite(pin, HIGH), analogWrite(pin, 255)
    EXPECT_DOUBLE_EQ(d.duty(), 1.0);
    EXPECT_TRUE(d.enable_level_at(12345));
}

struct Rig {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core{elf};
    hil::MotorDriverReader reader{core, hil::uno_default_board()};
    hil::UartLink uart{core};
};

TEST(MotorDriverReader, SetupLeavesBothBridgesOff) {
    Rig r;
    r.core.run_until(hil::s_to_cycles(1.0));
    r.reader.advance_to(r.core.cycle());
    for (std::size_t m = 0; m < 2; ++m) {
        EXPECT_FALSE(r.reader.drive(m).pwm_connected) << m;  // analogWrite(pin, 0) = digitalWrite LOW
        EXPECT_DOUBLE_EQ(r.reader.drive(m).duty(), 0.0) << m;
        EXPECT_TRUE(r.reader.drive(m).timer_running) << m;   // init() starts Timers 1 and 2
        EXPECT_FALSE(r.reader.drive(m).forward) << m;
    }
}

TEST(MotorDriverReader, FirstIterationOfCase1DrivesTheHandComputedDuties) {
    // First iteration, robot at rest at the origin, t = 0 (hand-worked):
    //   errx = 0.6, erry = 0, etheta = Angref = 1.571, errxr = 0.6, erryr = 0
    //   v = 0.2 cos(1.571) + kx 0.6 = 0.59996   (const int kx = 1.1 -> 1)
    //   w = 0.2 + 0.2 (6 x 0 + 8 sin(1.571)) = 1.8
    //   255 x 48 x 0.0054 x 0.164 = 10.8397
    //   Vdc1 = int(10.8397 (30.3 v + 1.92 w)) = int(234.5) = 234
    //   Vdc2 = int(10.8397 (30.3 v - 1.92 w)) = int(159.6) = 159
    Rig r;
    const auto stop = r.core.run_until_return_from(r.elf.require("delay"), hil::s_to_cycles(6.0));
    ASSERT_EQ(stop, hil::RunStop::kCondition);
    r.uart.send("1");
    r.core.run_until(r.core.cycle() + hil::ms_to_cycles(5.0));  // inside the first delay(9)
    r.reader.advance_to(r.core.cycle());
    EXPECT_EQ(r.reader.drive(0).ocr, 234);
    EXPECT_EQ(r.reader.drive(1).ocr, 159);
    EXPECT_TRUE(r.reader.drive(0).pwm_connected);
    EXPECT_TRUE(r.reader.drive(0).forward);
    EXPECT_TRUE(r.reader.drive(1).forward);
    EXPECT_NEAR(r.reader.drive(0).duty(), 234.0 / 255.0, 1e-12);
}

TEST(MotorDriverReader, OcrWritesTakeEffectAtTheNextTop) {
    Rig r;
    r.core.run_until(hil::s_to_cycles(0.1));
    avr_t* avr = r.core.raw();
    namespace reg = hil::atmega328p::reg;
    // What analogWrite(10, 100) does: COM1B1 on, OCR1B = 100 (high byte first).
    avr->data[reg::kTccr1A] = static_cast<uint8_t>(avr->data[reg::kTccr1A] | hil::atmega328p::com_bit::kComB1);
    avr->data[reg::kOcr1BH] = 0;
    avr->data[reg::kOcr1BL] = 100;
    avr_raise_irq(avr_iomem_getirq(avr, reg::kOcr1BL, nullptr, AVR_IOMEM_IRQ_ALL), 100);
    const hil::Cycles written = r.core.cycle();
    r.reader.advance_to(written);
    EXPECT_TRUE(r.reader.drive(0).pwm_connected);  // COM bits act at once
    EXPECT_NE(r.reader.drive(0).ocr, 100);         // OCR waits for TOP
    r.reader.advance_to(written + 32640);          // a TOP comes within one period
    EXPECT_EQ(r.reader.drive(0).ocr, 100);
    // Then a negative value: -30 -> 65506 in the 16-bit OCR1B; after any OCR
    // below TOP the output is low at TOP and stays low.
    avr->data[reg::kOcr1BH] = 0xFF;
    avr->data[reg::kOcr1BL] = 0xE2;
    avr_raise_irq(avr_iomem_getirq(avr, reg::kOcr1BL, nullptr, AVR_IOMEM_IRQ_ALL), 0xE2);
    r.reader.advance_to(written + 3 * 32640);
    EXPECT_EQ(r.reader.drive(0).ocr, 65506);
    EXPECT_DOUBLE_EQ(r.reader.drive(0).duty(), 0.0);
}

}  // namespace
}  // namespace ddmr::test
