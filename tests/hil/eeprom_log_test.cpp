// EEPROM log decoding: hand-worked bytes, a synthetic 0.6 m circle encoded as
// the sketch does, input validation, the CSV, and the reference firmware's
// own log of a known turning motion.
#include "hil/eeprom_log.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "hil/firmware_report.hpp"
#include "hil/uart_link.hpp"
#include "support/square_wave_input.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// The sketch's encoding: int(E*250.0) with avr-gcc's 32-bit double (a float
/// product), truncated toward zero, low 8 bits kept by EEPROM.write(uint8_t).
uint8_t encode(double e_m) {
    const auto counts = static_cast<int>(static_cast<float>(e_m) * 250.0f);
    return static_cast<uint8_t>(counts & 0xFF);
}

TEST(EepromLog, UnwrapsToTheValueNearestThePreviousSample) {
    // Previous sample 0.59 m -> int(147.5) = 147. Now x = 0.6 m -> 150 ->
    // byte 150; candidates 150 and 150 - 256 = -106: 150 is 3 from 147.
    EXPECT_EQ(hil::unwrap_counts(150, 147), 150);
    // 1.0 m = 250 counts, then 1.1 m = 275 counts -> byte 275 - 256 = 19;
    // candidates 19 and 275: 275 is 25 from 250.
    EXPECT_EQ(hil::unwrap_counts(19, 250), 275);
    // -0.1 m = -25 counts -> byte 231; from 0: -25 (25 away) beats 231.
    EXPECT_EQ(hil::unwrap_counts(231, 0), -25);
    // Below -0.512 m: -0.6 m = -150 -> byte 106; from -140: -150, not 106.
    EXPECT_EQ(hil::unwrap_counts(106, -140), -150);
    // A tie (128 counts either way) takes the lower value.
    EXPECT_EQ(hil::unwrap_counts(128, 0), -128);
}

TEST(EepromLog, FirstSampleIsASignedByte) {
    // -0.1 m -> int(-25.0) = -25 -> byte 231 -> int8 -25 -> -0.1 m.
    auto image = hil::EepromPort::erased(hil::atmega328p_mcu());
    image[0] = encode(-0.1);
    image[500] = encode(0.1);
    ASSERT_EQ(image[0], 231);
    ASSERT_EQ(image[500], 25);
    const auto log = hil::decode_eeprom_log(image, 1);
    ASSERT_EQ(log.size(), 1u);
    EXPECT_DOUBLE_EQ(log[0].x_m, -0.1);
    EXPECT_DOUBLE_EQ(log[0].y_m, 0.1);
    EXPECT_EQ(log[0].x_counts, -25);
    EXPECT_EQ(log[0].x_byte, 231);
    EXPECT_DOUBLE_EQ(log[0].t_s, 0.1);  // nominal: logged after 10 x 0.01 s
}

TEST(EepromLog, DecodesA0_6MetreCircleWithin4mm) {
    // A circle of radius 0.6 m through the origin, centre (0, 0.6), 120
    // samples (3.1 cm apart) from just after the origin: x reaches +-0.6 m
    // (+-150 counts) and y 1.2 m (300 counts), both outside a signed byte.
    // Truncation loses < 1 count = 4 mm; a wrong unwrap jumps 1.024 m.
    constexpr int kSamples = 120;
    constexpr double kR = 0.6;
    auto image = hil::EepromPort::erased(hil::atmega328p_mcu());
    std::vector<double> xs, ys;
    for (int k = 0; k < kSamples; ++k) {
        const double a = 2 * kPi * (k + 1) / kSamples;
        xs.push_back(kR * std::sin(a));
        ys.push_back(kR * (1 - std::cos(a)));
        image[static_cast<std::size_t>(2 * k)] = encode(xs.back());
        image[static_cast<std::size_t>(2 * k + 500)] = encode(ys.back());
    }
    const auto log = hil::decode_eeprom_log(image, kSamples);
    ASSERT_EQ(log.size(), static_cast<std::size_t>(kSamples));
    int max_y_counts = 0;
    for (std::size_t k = 0; k < log.size(); ++k) {
        // float(E) * 250 may round up to the next integer: allow 1e-6 m over.
        EXPECT_NEAR(log[k].x_m, xs[k], 0.004) << "sample " << k;
        EXPECT_NEAR(log[k].y_m, ys[k], 0.004) << "sample " << k;
        EXPECT_LT(std::abs(log[k].x_m), std::abs(xs[k]) + 1e-6) << "truncation is toward zero";
        if (k > 0) {
            EXPECT_LT(std::hypot(log[k].x_m - log[k - 1].x_m, log[k].y_m - log[k - 1].y_m), 0.05)
                << "sample " << k;
        }
        max_y_counts = std::max(max_y_counts, log[k].y_counts);
    }
    EXPECT_EQ(max_y_counts, 300);  // y = 1.2 m at k = 59: the byte wrapped (300 - 256 = 44)
    EXPECT_EQ(log[59].y_byte, 44);
}

TEST(EepromLog, RejectsSampleCountsOutsideTheLog) {
    const auto image = hil::EepromPort::erased(hil::atmega328p_mcu());
    EXPECT_NO_THROW((void)hil::decode_eeprom_log(image, 0));
    EXPECT_NO_THROW((void)hil::decode_eeprom_log(image, 250));  // x bytes 0..498
    for (const int bad : {-1, 251}) {
        try {
            (void)hil::decode_eeprom_log(image, bad);
            FAIL() << "sample count " << bad << " was accepted";
        } catch (const std::invalid_argument& e) {
            EXPECT_NE(std::string(e.what()).find(std::to_string(bad)), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW((void)hil::decode_eeprom_log(image, 3, {0.1, 0.2}), std::invalid_argument);
}

TEST(EepromLog, CsvHasFixedPrecisionRows) {
    // Sample 0: bytes 231, 25 -> (-0.1, 0.1); sample 1: bytes 0, 50 -> (0, 0.2).
    auto image = hil::EepromPort::erased(hil::atmega328p_mcu());
    image[0] = 231;
    image[500] = 25;
    image[2] = 0;
    image[502] = 50;
    const auto csv = hil::eeprom_log_csv(hil::decode_eeprom_log(image, 2, {0.1, 0.25}));
    EXPECT_EQ(csv,
              "sample,t_s,x_m,y_m\n"
              "0,0.100000,-0.100000,0.100000\n"
              "1,0.250000,0.000000,0.200000\n");
}

TEST(EepromLog, TimingComesFromTheXByteWrites) {
    // Origin at cycle 1,000. x writes at 1,601,000 (addr 0) and 3,201,000
    // (addr 2): 0.1 s and 0.2 s at 16 MHz; y writes and the earlier write
    // (before the origin) are ignored.
    const std::vector<hil::EepromWrite> writes = {
        {500, 40, 1}, {1'601'000, 0, 7}, {1'653'736, 500, 0}, {3'201'000, 2, 14}, {3'253'736, 502, 1}};
    const auto t = hil::eeprom_log_timing(writes, 1'000, kUnoClockHz, 1024);
    EXPECT_EQ(t.sample_count, 2);
    ASSERT_EQ(t.times_s.size(), 2u);
    EXPECT_DOUBLE_EQ(t.times_s[0], 0.1);
    EXPECT_DOUBLE_EQ(t.times_s[1], 0.2);
    // Sample 1 written without sample 0: a gap.
    EXPECT_THROW((void)hil::eeprom_log_timing({{1'601'000, 2, 7}}, 0, kUnoClockHz, 1024), std::invalid_argument);
}

TEST(EepromLog, DecodesTheFirmwaresLogOfAKnownTurn) {
    // Square waves give Count1 640 edges/s and Count2 500 edges/s. Per edge
    // the sketch's odometry advances 0.5*r1*radpuls = 0.5*0.03215*0.016362 m
    // per wheel edge and turns R*r1*radpuls = 7.874*0.03215*0.016362 rad per
    // Count1-minus-Count2 edge, whatever the loop period: a circle of radius
    // 0.5 * (640 + 500) / (7.874 * (640 - 500)) = 0.5171 m about (0, 0.5171)
    // from the origin heading +x. Its top, y = 1.034 m = 258 counts, wraps a
    // byte, as does x = +-0.517 m = +-129 counts.
    const double radius = 0.5 * (640 + 500) / (7.874 * (640 - 500));
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    hil::EepromWriteTiming timing(core);
    hil::EepromPort eeprom(core);
    hil::FirmwareReportParser parser(true);
    uart.set_listener([&](const hil::UartByte& b) {
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (parser.complete() || parser.error()) core.request_stop();
    });
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)),
              hil::RunStop::kCondition);
    SquareWaveInput left(core, 'D', 2, 25'000);   // 16e6 / 25,000 = 640 edges/s
    SquareWaveInput right(core, 'D', 3, 32'000);  // 16e6 / 32,000 = 500 edges/s
    const auto origin = core.cycle();
    uart.send("1");
    core.run_until(origin + hil::s_to_cycles(20.0, kUnoClockHz));
    ASSERT_TRUE(parser.complete()) << uart.text();
    const auto& report = parser.report();

    // 1200 iterations, a log call every 10: 120 samples; the sketch prints addr = 240.
    const auto timing_of_log = hil::eeprom_log_timing(timing.writes(), origin, kUnoClockHz, 1024);
    ASSERT_EQ(timing_of_log.sample_count, 120);
    EXPECT_EQ(report.addr.value_or(-1), 2.0 * timing_of_log.sample_count);
    const auto log = hil::decode_eeprom_log(eeprom.read_all(), timing_of_log.sample_count,
                                            timing_of_log.times_s);
    // The sketch's dump prints byte/250 with 3 decimals (j <= addr: one extra pair).
    ASSERT_EQ(report.eeprom_pairs.size(), log.size() + 1);
    int wrapped = 0;
    for (std::size_t k = 0; k < log.size(); ++k) {
        EXPECT_NEAR(log[k].x_byte / 250.0, report.eeprom_pairs[k].first, 5e-4) << "sample " << k;
        EXPECT_NEAR(log[k].y_byte / 250.0, report.eeprom_pairs[k].second, 5e-4) << "sample " << k;
        // On the circle, to within truncation (4 mm) and count quantisation
        // (measured: within 4.1 mm).
        const double d = std::hypot(log[k].x_m, log[k].y_m - radius);
        EXPECT_NEAR(d, radius, 0.01) << "sample " << k << " at (" << log[k].x_m << ", " << log[k].y_m << ")";
        if (k > 0) {
            EXPECT_GT(log[k].t_s, log[k - 1].t_s);
            EXPECT_LT(std::hypot(log[k].x_m - log[k - 1].x_m, log[k].y_m - log[k - 1].y_m), 0.05);
        }
        if (log[k].x_counts > 127 || log[k].x_counts < -128 || log[k].y_counts > 127) ++wrapped;
    }
    EXPECT_GT(wrapped, 0) << "the run never left the signed-byte range";
    // The last sample is logged after the last iteration: the printed end pose,
    // within truncation (< 4 mm) and print rounding (5e-5).
    EXPECT_NEAR(log.back().x_m, report.ex.value(), 0.004 + 5e-5);
    EXPECT_NEAR(log.back().y_m, report.ey.value(), 0.004 + 5e-5);
}

}  // namespace
TEST(EepromLog, AContractsLayoutAddressesScalesAndSignedness) {
    // x bytes at 100.., y bytes at 300.., one byte per sample, 100 counts per metre.
    hil::EepromImage image = hil::EepromPort::erased(hil::atmega328p_mcu());
    image[100] = 200;  // sample 0 x: 200 counts unsigned (2.00 m), -56 signed
    image[101] = 10;
    image[300] = 5;
    image[301] = 250;  // sample 1 y: 250 unsigned, -6 signed (no unwrap)
    hil::EepromLogLayout l;
    l.x_address = 100;
    l.y_address = 300;
    l.stride = 1;
    l.counts_per_metre = 100.0;
    l.unwrap = false;
    l.sample_period_s = 0.01;
    EXPECT_EQ(l.max_samples(1024), 200);  // x bytes below 300
    EXPECT_EQ(l.max_samples(4096), 200);
    EXPECT_EQ(l.max_samples(300), 0);  // the y series would start past the end
    auto s = hil::decode_eeprom_log(image, 2, {}, l);
    ASSERT_EQ(s.size(), 2u);
    EXPECT_DOUBLE_EQ(s[0].x_m, -0.56);
    EXPECT_DOUBLE_EQ(s[1].y_m, -0.06);
    EXPECT_DOUBLE_EQ(s[1].t_s, 0.02);
    l.is_signed = false;
    s = hil::decode_eeprom_log(image, 2, {}, l);
    EXPECT_DOUBLE_EQ(s[0].x_m, 2.0);
    EXPECT_DOUBLE_EQ(s[1].y_m, 2.5);
    EXPECT_THROW(hil::decode_eeprom_log(image, 201, {}, l), std::invalid_argument);
}

}  // namespace ddmr::test
