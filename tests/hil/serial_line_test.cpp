// Tests for hil/serial_line: a UART receiver reading a wire whose sender may
// run at another baud rate. Expected bytes worked out by hand (comments).
#include "hil/serial_line.hpp"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ddmr::hil {
namespace {

std::vector<LineByte> send(SerialLine& line, const std::string& text, double tx_bit) {
    std::vector<LineByte> out;
    double t = 100.0;
    for (const char c : text) {
        line.push(t, static_cast<uint8_t>(c), tx_bit, out);
        t += 10.0 * tx_bit;  // back to back
    }
    line.flush(out);
    return out;
}

std::string text_of(const std::vector<LineByte>& bytes) {
    std::string s;
    for (const auto& b : bytes) s.push_back(static_cast<char>(b.value));
    return s;
}

TEST(SerialLine, AvrBitTimeFromRegisters) {
    EXPECT_DOUBLE_EQ(SerialLine::avr_bit_cycles(207, true), 1664.0);   // 9600 baud as Arduino sets it
    EXPECT_DOUBLE_EQ(SerialLine::avr_bit_cycles(103, true), 832.0);    // 19200
    EXPECT_DOUBLE_EQ(SerialLine::avr_bit_cycles(103, false), 1664.0);  // 9600 without U2X
}

TEST(SerialLine, EqualRatesDecodeEveryByte) {
    SerialLine line(16e6 / 9600);  // the adapter: 1666.67 cycles per bit
    const auto out = send(line, "0.6m\r\nEND\r\n", 1664.0);
    EXPECT_EQ(text_of(out), "0.6m\r\nEND\r\n");
    EXPECT_EQ(line.framing_errors(), 0U);
}

TEST(SerialLine, TwoPercentApartStillDecodes) {
    // Sampling drifts 9.5 x 2 % = 19 % of a bit by the stop bit: inside it.
    SerialLine line(1664.0 * 1.02);
    const std::string all = [] {
        std::string s;
        for (int c = 0; c < 256; ++c) s.push_back(static_cast<char>(c));
        return s;
    }();
    const auto out = send(line, all, 1664.0);
    EXPECT_EQ(text_of(out), all);
    EXPECT_EQ(line.framing_errors(), 0U);
}

TEST(SerialLine, DoubleSpeedSenderReadsAsGarbage) {
    // 'A' = 0x41 at 832 cycles/bit, read at 1664: the edge at the start bit,
    // data samples at 2496, 4160, 5824, 7488 land on bits d2=0, d4=0, d6=1,
    // stop=1, the next four on the idle line (1); the stop sample (15808)
    // too: 0b11111100 = 0xFC, no framing error.
    SerialLine line(1664.0);
    std::vector<LineByte> out;
    line.push(0.0, 'A', 832.0, out);
    line.flush(out);
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].value, 0xFC);
    EXPECT_FALSE(out[0].framing_error);
    EXPECT_DOUBLE_EQ(out[0].cycle, 9.5 * 1664.0);
}

TEST(SerialLine, HalfSpeedSenderGivesAFramingError) {
    // 0x00 at 1664 cycles/bit is low for 9 of its bits; read at 832 every
    // sample, the stop bit's included (7904), is low: 0x00 with a framing
    // error, and no falling edge follows.
    SerialLine line(832.0);
    std::vector<LineByte> out;
    line.push(0.0, 0x00, 1664.0, out);
    line.flush(out);
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].value, 0x00);
    EXPECT_TRUE(out[0].framing_error);
    EXPECT_EQ(line.framing_errors(), 1U);
}

TEST(SerialLine, MismatchedReportTextIsNotTheText) {
    SerialLine line(16e6 / 9600);
    const auto out = send(line, "0.6m\r\nEND\r\n", 832.0);
    EXPECT_NE(text_of(out), "0.6m\r\nEND\r\n");
    EXPECT_EQ(text_of(out).find("END"), std::string::npos);
}

TEST(SerialLine, IdleGapsBetweenFramesDecodeAsTheyArrive) {
    // One idle bit between frames: each byte is decoded as soon as the next
    // frame starts (its samples are then settled), the last one at flush.
    const std::string text = "pdt1,12.5,pdt2,9.75\r\n";
    SerialLine line(16e6 / 9600);
    std::vector<LineByte> out;
    double t = 0.0;
    for (std::size_t i = 0; i < text.size(); ++i) {
        line.push(t, static_cast<uint8_t>(text[i]), 1664.0, out);
        EXPECT_EQ(out.size(), i) << "byte " << i;
        t += 11.0 * 1664.0;
    }
    line.flush(out);
    EXPECT_EQ(text_of(out), text);
}

TEST(SerialLine, HalfSpeedTextIsFramingErrors) {
    SerialLine line(16e6 / 9600);
    const auto out = send(line, "pdt1,12.5\r\n", 3328.0);
    EXPECT_GT(line.framing_errors(), 0U);
    EXPECT_NE(text_of(out), "pdt1,12.5\r\n");
}

TEST(SerialLine, FramesNeverOverlap) {
    // A frame pushed before the previous one ends starts when it ends.
    SerialLine line(1664.0);
    std::vector<LineByte> out;
    line.push(0.0, 'O', 1664.0, out);
    line.push(10.0, 'K', 1664.0, out);
    line.flush(out);
    EXPECT_EQ(text_of(out), "OK");
    EXPECT_DOUBLE_EQ(out[1].cycle, 10.0 * 1664.0 + 9.5 * 1664.0);
}

TEST(SerialLine, SettleDeliversTheLastByteOnceItsStopBitIsSampled) {
    SerialLine line(1664.0);
    std::vector<LineByte> out;
    line.push(0.0, '\n', 1664.0, out);
    line.settle(9.5 * 1664.0 - 1.0, out);
    EXPECT_TRUE(out.empty());  // the stop bit is sampled at 15808
    line.settle(9.5 * 1664.0 + 1.0, out);
    ASSERT_EQ(out.size(), 1U);
    EXPECT_EQ(out[0].value, '\n');
    // A frame pushed for an earlier time starts when the line is free: after
    // the previous frame's stop bit (16640) and not before the settled time.
    line.push(0.0, 'A', 1664.0, out);
    line.settle(40000.0, out);
    line.push(0.0, 'B', 1664.0, out);
    line.flush(out);
    ASSERT_EQ(out.size(), 3U);
    EXPECT_DOUBLE_EQ(out[1].cycle, 10.0 * 1664.0 + 9.5 * 1664.0);
    EXPECT_DOUBLE_EQ(out[2].cycle, 40000.0 + 9.5 * 1664.0);
}

TEST(SerialLine, RefusesNonPositiveBitTimes) {
    EXPECT_THROW(SerialLine(0.0), std::invalid_argument);
    SerialLine line(1664.0);
    std::vector<LineByte> out;
    EXPECT_THROW(line.push(0.0, 1, -1.0, out), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::hil
