// MotorDriverReader: the bridge drive decoded from Timer1/Timer2 and PORTB,
// checked against the datasheet's phase-correct waveform and against what
// the reference firmware writes.
#include "hil/motor_driver_reader.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <sim_avr.h>
#include <sim_io.h>
#include <sim_irq.h>

#include "hil/atmega328p.hpp"
#include "hil/uart_link.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using plant::BridgeState;

/// Writes `value` to a data-space register as the firmware would, so the
/// parts watching it are notified.
void poke(hil::AvrCore& core, uint16_t reg, uint8_t value) {
    core.raw()->data[reg] = value;
    avr_raise_irq(avr_iomem_getirq(core.raw(), reg, nullptr, AVR_IOMEM_IRQ_ALL), value);
}

struct Rig {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core{elf};
    hil::MotorDriverReader reader{core, hil::default_board()};
    hil::UartLink uart{core};
};

TEST(MotorDriverReader, SetupLeavesBothBridgesCoasting) {
    Rig r;
    r.core.run_until(hil::s_to_cycles(1.0, kUnoClockHz));
    r.reader.advance_to(r.core.cycle());
    for (std::size_t m = 0; m < 2; ++m) {
        const int pwm_pin = m == 0 ? 10 : 11;
        EXPECT_FALSE(r.reader.pins().timer_driven(pwm_pin)) << m;  // analogWrite(pin, 0) = digitalWrite LOW
        EXPECT_EQ(r.reader.pins().mode(pwm_pin), hil::PinMode::output) << m;
        EXPECT_TRUE(r.reader.pins().timer_of(pwm_pin)->running()) << m;  // init() starts Timers 1 and 2
        const plant::BridgeInput in = r.reader.input_at(m, r.core.cycle());
        EXPECT_EQ(in.state, BridgeState::coast) << m;  // PWM (enable) low
        EXPECT_DOUBLE_EQ(in.duty, 0.0) << m;
        EXPECT_FALSE(in.forward) << m;  // DIR written low in setup()
    }
    EXPECT_TRUE(r.reader.wiring_warnings().empty());
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
    const auto stop = r.core.run_until_return_from(r.elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz));
    ASSERT_EQ(stop, hil::RunStop::kCondition);
    r.uart.send("1");
    r.core.run_until(r.core.cycle() + hil::ms_to_cycles(5.0, kUnoClockHz));  // inside the first delay(9)
    const hil::Cycles now = r.core.cycle();
    r.reader.advance_to(now);
    EXPECT_DOUBLE_EQ(r.reader.pins().duty(10), 234.0 / 255.0);  // phase correct: OCR / TOP
    EXPECT_DOUBLE_EQ(r.reader.pins().duty(11), 159.0 / 255.0);
    EXPECT_TRUE(r.reader.pins().timer_driven(10));
    const plant::BridgeInput right = r.reader.input_at(0, now);
    EXPECT_TRUE(right.forward);
    EXPECT_DOUBLE_EQ(right.duty, 234.0 / 255.0);
    EXPECT_TRUE(r.reader.input_at(1, now).forward);
    // Switched: forward while the enable is high, coast while it is low.
    for (hil::Cycles c = now; c < now + 32640; c = r.reader.next_change_after(0, c)) {
        EXPECT_EQ(r.reader.state_at(0, c), r.reader.pins().level_at(10, c) ? BridgeState::forward : BridgeState::coast);
    }
}

TEST(MotorDriverReader, OcrWritesTakeEffectAtTheNextTop) {
    Rig r;
    r.core.run_until(hil::s_to_cycles(0.1, kUnoClockHz));
    avr_t* avr = r.core.raw();
    namespace reg = hil::atmega328p::reg;
    // What analogWrite(10, 100) does: COM1B1 on, OCR1B = 100 (high byte first).
    avr->data[reg::kTccr1A] = static_cast<uint8_t>(avr->data[reg::kTccr1A] | hil::atmega328p::com_bit::kComB1);
    avr->data[reg::kOcr1BH] = 0;
    avr->data[reg::kOcr1BL] = 100;
    avr_raise_irq(avr_iomem_getirq(avr, reg::kOcr1BL, nullptr, AVR_IOMEM_IRQ_ALL), 100);
    const hil::Cycles written = r.core.cycle();
    r.reader.advance_to(written);
    EXPECT_TRUE(r.reader.pins().timer_driven(10));          // COM bits act at once
    EXPECT_NE(r.reader.pins().duty(10), 100.0 / 255.0);     // OCR waits for TOP
    r.reader.advance_to(written + 32640);                   // a TOP comes within one period
    EXPECT_DOUBLE_EQ(r.reader.pins().duty(10), 100.0 / 255.0);
    // Then a negative value: -30 -> 65506 in the 16-bit OCR1B; after any OCR
    // below TOP the output is low at TOP and stays low.
    avr->data[reg::kOcr1BH] = 0xFF;
    avr->data[reg::kOcr1BL] = 0xE2;
    avr_raise_irq(avr_iomem_getirq(avr, reg::kOcr1BL, nullptr, AVR_IOMEM_IRQ_ALL), 0xE2);
    r.reader.advance_to(written + 3 * 32640);
    EXPECT_DOUBLE_EQ(r.reader.pins().duty(10), 0.0);
}

/// An L298N with the EN jumper fitted on the right wheel (IN1 = 7, IN2 = 8)
/// and a TB6612 on the left (PWM 9, IN1 4, IN2 5, STBY A0): pins the
/// reference firmware leaves alone, driven here by register writes.
hil::BoardWiring two_drivers() {
    hil::BoardWiring b = hil::default_board();
    hil::MotorWiring& right = b.wheel[0].motor;
    right = hil::MotorWiring{};
    right.driver = plant::DriverType::l298n;
    right[hil::DriverRole::en] = hil::InputWire{true, true, -1, 0, {}};
    right[hil::DriverRole::in1] = hil::InputWire{true, false, 7, 0, {}};
    right[hil::DriverRole::in2] = hil::InputWire{true, false, 8, 0, {}};
    hil::MotorWiring& left = b.wheel[1].motor;
    left = hil::MotorWiring{};
    left.driver = plant::DriverType::tb6612;
    left.reversed = true;
    left[hil::DriverRole::pwm] = hil::InputWire{true, false, 9, 0, {}};
    left[hil::DriverRole::in1] = hil::InputWire{true, false, 4, 0, {}};
    left[hil::DriverRole::in2] = hil::InputWire{true, false, 5, 0, {}};
    left[hil::DriverRole::stby] = hil::InputWire{true, false, 14, 0, {}};
    return b;
}

TEST(MotorDriverReader, TruthTablesFromPinLevels) {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core{elf};
    hil::MotorDriverReader reader{core, two_drivers()};
    core.run_until(hil::s_to_cycles(0.1, kUnoClockHz));
    namespace reg = hil::atmega328p::reg;
    const auto now = [&] { return core.cycle(); };
    // Right L298N: IN1 = IN2 = floating inputs (read low): EN high -> brake.
    EXPECT_EQ(reader.state_at(0, now()), BridgeState::brake);
    // pinMode(7, OUTPUT); digitalWrite(7, HIGH): forward.
    poke(core, static_cast<uint16_t>(reg::kPinD + 1), static_cast<uint8_t>(core.data(reg::kPinD + 1) | 0x80));
    poke(core, reg::kPortD, static_cast<uint8_t>(core.data(reg::kPortD) | 0x80));
    EXPECT_EQ(reader.state_at(0, now()), BridgeState::forward);
    // Pin 8 left an input with its pull-up on (PORTB0 = 1): IN2 reads high -> brake.
    poke(core, reg::kPortB, static_cast<uint8_t>(core.data(reg::kPortB) | 0x01));
    EXPECT_EQ(reader.state_at(0, now()), BridgeState::brake);
    // Left TB6612, reversed: STBY (A0) floating -> standby (coast).
    EXPECT_EQ(reader.state_at(1, now()), BridgeState::coast);
    // STBY high, IN1 high (pin 4), IN2 low, PWM (pin 9) high: CW = forward,
    // which the swapped leads turn into reverse.
    poke(core, static_cast<uint16_t>(reg::kPinC + 1), 0x01);
    poke(core, reg::kPortC, 0x01);
    poke(core, static_cast<uint16_t>(reg::kPinD + 1), static_cast<uint8_t>(core.data(reg::kPinD + 1) | 0x30));
    poke(core, reg::kPortD, static_cast<uint8_t>((core.data(reg::kPortD) | 0x10) & ~0x20));
    poke(core, reg::kDdrB, static_cast<uint8_t>(core.data(reg::kDdrB) | 0x02));
    poke(core, reg::kPortB, static_cast<uint8_t>(core.data(reg::kPortB) | 0x02));
    EXPECT_EQ(reader.state_at(1, now()), BridgeState::reverse);
    const plant::BridgeInput in = reader.input_at(1, now());
    EXPECT_FALSE(in.forward);
    EXPECT_DOUBLE_EQ(in.duty, 1.0);
    // PWM low: short brake.
    poke(core, reg::kPortB, static_cast<uint8_t>(core.data(reg::kPortB) & ~0x02));
    EXPECT_EQ(reader.state_at(1, now()), BridgeState::brake);
    // Pin 8 (right IN2) was never made an output: one warning naming it.
    const auto warnings = reader.wiring_warnings();
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_EQ(warnings[0], "pin 8 (right L298N IN2) is never set as an output: the driver sees only the pull-up (high)");
}

/// The firmware at rest (case 1 not started: both enables digitalWrite LOW,
/// Timer1 in the core's phase-correct mode at /64), then Timer1's registers
/// poked as a sketch would write them.
struct TakeoverRig {
    Rig r;
    TakeoverRig() { r.core.run_until(hil::s_to_cycles(0.5, kUnoClockHz)); }
    /// TCCR1A = COM1B1 | wgm10 (analogWrite(10) sets COM1B1), TCCR1B keeps /64.
    void timer1(bool phase_correct) {
        poke(r.core, hil::atmega328p::reg::kTccr1A, static_cast<uint8_t>(0x20 | (phase_correct ? 0x01 : 0x00)));
    }
    void run_ms(double ms) { r.core.run_until(r.core.cycle() + hil::ms_to_cycles(ms, kUnoClockHz)); }
    [[nodiscard]] std::vector<std::string> takeovers() const {
        std::vector<std::string> out;
        for (const std::string& w : r.reader.wiring_warnings()) {
            if (w.find("Timer") != std::string::npos) out.push_back(w);
        }
        return out;
    }
};

TEST(MotorDriverReader, AnalogWriteOnATimerTakenIntoNormalModeIsWarnedAbout) {
    // The Servo library's TCCR1A = 0 leaves Timer1 in normal mode; a later
    // analogWrite(10, x) sets COM1B1 there: "clear OC1B on compare match",
    // no PWM. Held for 2 ms (> the 1 ms a register-by-register set-up may take).
    TakeoverRig t;
    t.timer1(false);
    const double from_s = t.r.core.seconds();
    t.run_ms(2.0);
    const auto w = t.takeovers();
    ASSERT_EQ(w.size(), 1u);
    EXPECT_NE(w[0].find("pin 10 ("), std::string::npos) << w[0];
    EXPECT_NE(w[0].find("is OC1B of Timer1, which the firmware ran in normal mode (WGM 0) from " +
                        fmt::format("{:.4f}", from_s) + " s: analogWrite(10) makes no PWM there"),
              std::string::npos)
        << w[0];
}

TEST(MotorDriverReader, APwmModeOrABriefSetUpStateIsNoTakeover) {
    TakeoverRig t;
    t.timer1(true);  // analogWrite in the core's phase-correct mode: PWM
    t.run_ms(2.0);
    EXPECT_TRUE(t.takeovers().empty());
    t.timer1(false);  // normal mode for 0.5 ms, as while a sketch sets its own PWM mode up
    t.run_ms(0.5);
    t.timer1(true);
    t.run_ms(2.0);
    EXPECT_TRUE(t.takeovers().empty());
}

}  // namespace
}  // namespace ddmr::test
