// UartLink: bytes captured with their cycle, frame pacing as on the chip (or
// as simavr 1.6 does it), and sending gated by the receiver's XON.
#include "hil/uart_link.hpp"

#include <gtest/gtest.h>

#include <map>

#include "support/reference_run.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

/// The most common gap between consecutive UDR0 writes: in the report,
/// Serial's 64-byte buffer is full and the UART sends back to back.
hil::Cycles mode_gap(const std::vector<hil::UartByte>& bytes) {
    std::map<hil::Cycles, int> histogram;
    for (std::size_t i = 1; i < bytes.size(); ++i) ++histogram[bytes[i].cycle - bytes[i - 1].cycle];
    hil::Cycles mode = 0;
    int best = 0;
    for (const auto& [gap, n] : histogram) {
        if (n > best) {
            best = n;
            mode = gap;
        }
    }
    return mode;
}

/// Mean cycles per byte over the last `n` bytes (the EEPROM dump, sent back
/// to back). Single gaps between UDR0 writes can be shorter than a frame: the
/// data register is double-buffered, so a write can follow the previous one
/// as soon as that byte moves to the shift register.
double mean_gap_of_last(const std::vector<hil::UartByte>& bytes, std::size_t n) {
    const auto& last = bytes.back();
    const auto& first = bytes[bytes.size() - n];
    return static_cast<double>(last.cycle - first.cycle) / static_cast<double>(n - 1);
}

TEST(UartLink, ChipTimingPacesAn8N1ByteIn16640Cycles) {
    // Serial.begin(9600) on a 16 MHz Uno: U2X0 = 1, UBRR0 = (16e6/4/9600 - 1)/2
    // = 207, so a bit is (207 + 1) * 8 = 1664 cycles and an 8N1 frame (start +
    // 8 data + stop = 10 bits) 16,640 cycles: 9615 baud, 0.16 % fast.
    const auto run = run_reference_case('1', hil::UartTiming::kChip);
    ASSERT_TRUE(run.report_complete);
    EXPECT_EQ(run.cycles_per_byte, 16640u);
    EXPECT_EQ(mode_gap(run.bytes), 16640u);
    ASSERT_GT(run.bytes.size(), 1500u);
    EXPECT_NEAR(mean_gap_of_last(run.bytes, 1500), 16640.0, 16640.0 * 0.001);
}

TEST(UartLink, SimavrTimingCountsAParityBit) {
    // simavr 1.6 adds a parity bit to every frame: 11 x 1664 = 18,304 cycles.
    const auto run = run_reference_case('2', hil::UartTiming::kSimavr);
    ASSERT_TRUE(run.report_complete);
    EXPECT_EQ(run.cycles_per_byte, 18304u);
    EXPECT_EQ(mode_gap(run.bytes), 18304u);
}

TEST(UartLink, BytesSentBeforeSerialBeginWaitForTheReceiver) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    uart.send("1");  // at reset: RXEN is off, simavr would drop the byte
    EXPECT_EQ(uart.pending(), 1u);
    core.run_until(hil::s_to_cycles(0.1, kUnoClockHz));  // Serial.begin() has enabled RX
    EXPECT_EQ(uart.pending(), 0u);
    // The byte waited in Serial's buffer through delay(5000): case 1 runs.
    core.run_until(hil::s_to_cycles(5.1, kUnoClockHz));
    EXPECT_EQ(uart.text(), "0.6m\r\n");
}

TEST(UartLink, CapturesEachByteWithItsCycle) {
    const auto run = run_reference_case('2');
    ASSERT_FALSE(run.bytes.empty());
    std::string rebuilt;
    for (std::size_t i = 0; i < run.bytes.size(); ++i) {
        rebuilt.push_back(static_cast<char>(run.bytes[i].value));
        if (i > 0) {
            EXPECT_GT(run.bytes[i].cycle, run.bytes[i - 1].cycle);
        }
    }
    EXPECT_EQ(rebuilt, run.text);
    EXPECT_GT(run.bytes.front().cycle, run.ready_cycle);
}

}  // namespace
}  // namespace ddmr::test
