// Tests for plant/pwm_waveform: Uno phase-correct PWM timing (16 MHz / 64 / 510).
#include "plant/pwm_waveform.hpp"

#include <gtest/gtest.h>

namespace ddmr::plant {
namespace {

TEST(PwmWaveform, PeriodIs32640CyclesOr490Hz) {
    EXPECT_EQ(PhaseCorrectPwm::kPeriodCycles, 32640);  // 2 * 255 * 64
    // 16e6 / 32640 = 490.196 Hz
    EXPECT_NEAR(1.0 / cycles_to_s(PhaseCorrectPwm::kPeriodCycles), 490.196, 1e-3);
    EXPECT_EQ(s_to_cycles(1e-3), 16000);
}

TEST(PwmWaveform, DutyToOcrRoundsLikeAnalogWrite) {
    EXPECT_EQ(PhaseCorrectPwm::ocr_for_duty(0.2), 51);   // 51.0
    EXPECT_EQ(PhaseCorrectPwm::ocr_for_duty(0.5), 128);  // 127.5 rounds up
    EXPECT_EQ(PhaseCorrectPwm::ocr_for_duty(1.0), 255);
    EXPECT_EQ(PhaseCorrectPwm::ocr_for_duty(-3.0), 0);
}

TEST(PwmWaveform, HighForTwoOcrTimes64CyclesCentredOnBottom) {
    const PhaseCorrectPwm pwm{51, 0};
    // on = 2*51*64 = 6528 cycles: high on [0, 3264) and [32640-3264, 32640).
    EXPECT_EQ(pwm.on_cycles(), 6528);
    EXPECT_TRUE(pwm.level_at(0));
    EXPECT_TRUE(pwm.level_at(3263));
    EXPECT_FALSE(pwm.level_at(3264));
    EXPECT_FALSE(pwm.level_at(29375));
    EXPECT_TRUE(pwm.level_at(29376));
    EXPECT_TRUE(pwm.level_at(32640 + 10));  // periodic
    std::int64_t high = 0;
    for (std::int64_t c = 0; c < PhaseCorrectPwm::kPeriodCycles; ++c) high += pwm.level_at(c) ? 1 : 0;
    EXPECT_EQ(high, 6528);  // duty = 51/255 = 0.2 exactly
    EXPECT_DOUBLE_EQ(pwm.duty(), 0.2);
}

TEST(PwmWaveform, NextEdgeWalksTheEdges) {
    const PhaseCorrectPwm pwm{51, 100};  // BOTTOM at cycle 100
    EXPECT_EQ(pwm.next_edge_after(100), 100 + 3264);           // falling
    EXPECT_EQ(pwm.next_edge_after(100 + 3264), 100 + 29376);   // rising
    EXPECT_EQ(pwm.next_edge_after(100 + 29376), 100 + 32640 + 3264);
    // Every reported edge really changes the level.
    std::int64_t c = 0;
    for (int k = 0; k < 10; ++k) {
        const std::int64_t e = pwm.next_edge_after(c);
        EXPECT_NE(pwm.level_at(e), pwm.level_at(e - 1));
        for (std::int64_t m = c + 1; m < e; m += 97) EXPECT_EQ(pwm.level_at(m), pwm.level_at(c));
        c = e;
    }
}

TEST(PwmWaveform, ZeroAndFullAreConstant) {
    EXPECT_EQ((PhaseCorrectPwm{0, 0}.next_edge_after(5)), PhaseCorrectPwm::kNever);
    EXPECT_EQ((PhaseCorrectPwm{255, 0}.next_edge_after(5)), PhaseCorrectPwm::kNever);
    EXPECT_FALSE((PhaseCorrectPwm{0, 0}.level_at(0)));
    EXPECT_TRUE((PhaseCorrectPwm{255, 0}.level_at(16320)));  // even at TOP
}

}  // namespace
}  // namespace ddmr::plant
