// AdcInput: voltages on analog pins give the codes of ATmega328P datasheet
// section 24.7, ADC = floor(VIN * 1024 / VREF) clamped to 0..1023, through
// the firmware's own conversions (tests/firmware/adc_fixture.c: AVCC
// reference on A0..A5, the internal 1.1 V on A0).
#include "hil/adc_input.hpp"

#include <gtest/gtest.h>

#include <string>

#include "support/fixture_core.hpp"

namespace ddmr::test {
namespace {

constexpr int kA0 = 14;  // Uno: A0 = 14 .. A5 = 19
/// One round of adc_fixture: 7 conversions of 13 ADC clocks at /128 (1664
/// cycles each; the first 25 clocks) plus the loop: well under 14,000 cycles.
constexpr hil::Cycles kRoundCycles = 14'000;

struct AdcRig {
    FixtureCore f{"adc_fixture"};
    hil::AdcInput adc{f.core};
    /// Runs until the fixture has finished `n` more rounds.
    void rounds(uint8_t n) {
        const auto target = static_cast<uint8_t>(f.u8("rounds") + n);
        ASSERT_TRUE(f.run_until_u8("rounds", target, kRoundCycles * n + kRoundCycles));
    }
};

TEST(AdcInput, DatasheetCodes) {
    // Worked by hand from VIN * 1024 / VREF:
    EXPECT_EQ(hil::AdcInput::datasheet_code(2.5, 5.0), 512);   // 2.5 * 1024 / 5 = 512
    EXPECT_EQ(hil::AdcInput::datasheet_code(1.0, 5.0), 204);   // 204.8
    EXPECT_EQ(hil::AdcInput::datasheet_code(5.0, 5.0), 1023);  // 1024: 0x3FF is VREF - 1 LSB
    EXPECT_EQ(hil::AdcInput::datasheet_code(-0.2, 5.0), 0);
    EXPECT_EQ(hil::AdcInput::datasheet_code(0.55, 1.1), 512);
}

TEST(AdcInput, AnalogReadReturnsTheDatasheetCode) {
    AdcRig r;
    r.adc.set_voltage(kA0 + 0, 2.5);   // 512 (simavr 1.6 alone: 2500 * 1023 / 5000 = 511)
    r.adc.set_voltage(kA0 + 1, 0.0);   // 0
    r.adc.set_voltage(kA0 + 2, 5.0);   // 1023
    r.adc.set_voltage(kA0 + 3, 1.0);   // 204
    r.adc.set_voltage(kA0 + 4, 6.0);   // above VREF: 1023
    r.adc.set_voltage(kA0 + 5, 3.3);   // 3.3 * 1024 / 5 = 675.84 -> 675
    r.rounds(2);
    EXPECT_EQ(r.f.u16("codes", 0), 512u);
    EXPECT_EQ(r.f.u16("codes", 1), 0u);
    EXPECT_EQ(r.f.u16("codes", 2), 1023u);
    EXPECT_EQ(r.f.u16("codes", 3), 204u);
    EXPECT_EQ(r.f.u16("codes", 4), 1023u);
    EXPECT_EQ(r.f.u16("codes", 5), 675u);
    // A0 against the internal 1.1 V: 2.5 V is above it.
    EXPECT_EQ(r.f.u16("code_1v1"), 1023u);
}

// analogRead()'s wait for ADSC to clear is skipped by fast-forward: the
// conversion's end is a cycle timer of simavr's ADC, which bounds every jump,
// and a read of ADCSRA changes nothing in AdcInput (IoReads::kIgnored). The
// inputs are sawtooths of 5 V per 1021 cycles (about one code per cycle), so
// a sample taken one cycle off would read another code: the codes and the
// rounds' cycles are those of executing every pass.
TEST(AdcInput, ConversionWaitsAreSkippedExactly) {
    AdcRig on;
    AdcRig off;
    for (AdcRig* r : {&on, &off}) {
        for (int n = 0; n < 6; ++n) {
            r->adc.set_voltage(kA0 + n, [n](hil::Cycles c) {
                return 5.0 * static_cast<double>((c + 131U * static_cast<unsigned>(n)) % 1021U) / 1021.0;
            });
        }
    }
    on.f.core.set_fast_forward(true);
    off.f.core.set_fast_forward(false);
    for (hil::Cycles t = 50'000; t <= 1'000'000; t += 50'000) {
        on.f.core.run_until(t);
        off.f.core.run_until(t);
        ASSERT_EQ(on.f.core.cycle(), off.f.core.cycle());
        ASSERT_EQ(on.f.u8("rounds"), off.f.u8("rounds")) << "at cycle " << t;
        for (std::size_t n = 0; n < 6; ++n) ASSERT_EQ(on.f.u16("codes", n), off.f.u16("codes", n)) << "A" << n;
        ASSERT_EQ(on.f.u16("code_1v1"), off.f.u16("code_1v1"));
    }
    EXPECT_GT(on.f.u8("rounds"), 60U);  // under 14,000 cycles each
    ASSERT_NE(on.f.core.fast_forward(), nullptr);
    // Seven waits of 1664 cycles (the first 3200) make most of a round.
    EXPECT_GT(on.f.core.fast_forward()->stats().cycles_skipped, 600'000U);
}

TEST(AdcInput, TheInternalReferenceIsTheBandgap) {
    AdcRig r;
    r.adc.set_voltage(kA0, 0.55);
    r.rounds(2);
    EXPECT_EQ(r.f.u16("codes", 0), 112u);  // 0.55 * 1024 / 5 = 112.64
    EXPECT_EQ(r.f.u16("code_1v1"), 512u);  // 0.55 * 1024 / 1.1 = 512
}

TEST(AdcInput, AFunctionOfTimeIsSampledAtTheSampleAndHoldInstant) {
    AdcRig r;
    // A ramp of 1 V per 20,000 cycles: 192 cycles move it by 9.6 mV, about 2 LSB.
    r.adc.set_voltage(kA0, [](hil::Cycles c) { return static_cast<double>(c % 100'000) / 20'000.0; });
    r.rounds(3);
    const auto& s = r.adc.samples();
    ASSERT_GE(s.size(), 6u);
    // Table 24-1: sample-and-hold 13.5 ADC clocks after the start of the
    // first conversion, 1.5 after the others; the ADC clock is 128 cycles.
    EXPECT_EQ(s[0].sample_cycle - s[0].start_cycle, 1728u);
    EXPECT_EQ(s[1].sample_cycle - s[1].start_cycle, 192u);
    for (const auto& x : s) {
        EXPECT_EQ(x.channel, 0);
        EXPECT_DOUBLE_EQ(x.vin_v, static_cast<double>(x.sample_cycle % 100'000) / 20'000.0);
        EXPECT_EQ(x.code, hil::AdcInput::datasheet_code(x.vin_v, x.vref_v));
    }
    // The firmware got the code of the latest conversion against each reference.
    const hil::AdcSample* avcc = nullptr;
    const hil::AdcSample* bandgap = nullptr;
    for (const auto& x : s) (x.vref_v == 5.0 ? avcc : bandgap) = &x;
    ASSERT_NE(avcc, nullptr);
    ASSERT_NE(bandgap, nullptr);
    EXPECT_EQ(r.f.u16("codes", 0), avcc->code);
    EXPECT_EQ(r.f.u16("code_1v1"), bandgap->code);
    // Sampled at the start instead, the code would differ by about 2 LSB.
    EXPECT_NE(avcc->code, hil::AdcInput::datasheet_code(
                              static_cast<double>(avcc->start_cycle % 100'000) / 20'000.0, 5.0));
}

void expect_refused(const hil::BoardDescription& board, int pin, const std::string& words) {
    expect_invalid_argument([&] { (void)hil::AdcInput::channel_of(board, pin); }, words);
}

TEST(AdcInput, ChannelsOfTheBoardsPins) {
    const auto& uno = hil::board_description(hil::BoardModel::uno);
    const auto& nano = hil::board_description(hil::BoardModel::nano);
    const auto& mega = hil::board_description(hil::BoardModel::mega2560);
    EXPECT_EQ(hil::AdcInput::channel_of(uno, 14), 0);
    EXPECT_EQ(hil::AdcInput::channel_of(uno, 19), 5);
    EXPECT_EQ(hil::AdcInput::channel_of(nano, 21), 7);  // A7: analog only
    EXPECT_EQ(hil::AdcInput::channel_of(mega, 54), 0);
    EXPECT_EQ(hil::AdcInput::channel_of(mega, 61), 7);
    expect_refused(uno, 13, "pin 13 of the Arduino Uno has no ADC input");
    expect_refused(uno, 20, "pin 20");
    EXPECT_EQ(hil::AdcInput::channel_of(mega, 62), 8);   // A8 = ADC8 (MUX5)
    EXPECT_EQ(hil::AdcInput::channel_of(mega, 69), 15);  // A15
    expect_refused(mega, 70, "pin 70 of the Arduino Mega 2560 has no ADC input (analog pins A0..A15)");
}

TEST(AdcInput, TheMegasADC8ToADC15AreConverted) {
    // simavr 1.6 alone converts what lies past its adc_values[8] for these.
    FixtureCore f{"adc_fixture_atmega2560", hil::BoardModel::mega2560};
    hil::AdcInput adc{f.core};
    constexpr int kMegaA0 = 54;
    constexpr int kMegaA8 = 62;
    adc.set_voltage(kMegaA0, 2.001);    // 2.001 * 1024 / 5 = 409.8 -> 409
    adc.set_voltage(kMegaA8 + 0, 1.0);  // 1.0 * 1024 / 5 = 204.8 -> 204
    adc.set_voltage(kMegaA8 + 1, 2.5);  // 512
    adc.set_voltage(kMegaA8 + 2, 5.0);  // 1023
    adc.set_voltage(kMegaA8 + 3, 0.0);  // 0
    // A second AdcInput on the same core (each analog part has its own) finds
    // the entries the first one rewrote.
    hil::AdcInput other{f.core};
    other.set_voltage(kMegaA8 + 5, 3.3);  // 675.84 -> 675 (A12 = ADC12 has none)
    // A round: 13 conversions of 1664 cycles (the first 3200) and the loop.
    ASSERT_TRUE(f.run_until_u8("rounds", 2, 2 * 30'000));
    EXPECT_EQ(f.u16("codes", 0), 409u);
    EXPECT_EQ(f.u16("codes_high", 0), 204u);
    EXPECT_EQ(f.u16("codes_high", 1), 512u);
    EXPECT_EQ(f.u16("codes_high", 2), 1023u);
    EXPECT_EQ(f.u16("codes_high", 3), 0u);
    EXPECT_EQ(f.u16("codes_high", 5), 675u);
    // REFS1:0 = 11 is 2.56 V on the 2560 (Table 26-3): 2.001 * 1024 / 2.56 = 800.4.
    EXPECT_EQ(f.u16("code_1v1"), 800u);
    // Each conversion was recorded on its own channel.
    bool saw_adc13 = false;
    for (const auto& s : other.samples()) saw_adc13 = saw_adc13 || s.channel == 13;
    EXPECT_TRUE(saw_adc13);
}

TEST(AdcInput, RefusesASupplyOutsideTheDatasheet) {
    FixtureCore f{"adc_fixture"};
    EXPECT_THROW(hil::AdcInput(f.core, hil::AdcSupply{6.0, 0.0}), std::invalid_argument);
    EXPECT_THROW(hil::AdcInput(f.core, hil::AdcSupply{5.0, 0.5}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::test
