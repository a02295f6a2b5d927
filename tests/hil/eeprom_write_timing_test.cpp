// EepromWriteTiming: the reference firmware's case-1 log writes, timed as on
// the ATmega328P (datasheet Table 8-2) and as simavr 1.6 does it.
#include "hil/eeprom_write_timing.hpp"

#include <gtest/gtest.h>

#include <optional>

#include "hil/eeprom_port.hpp"
#include "hil/uart_link.hpp"
#include "support/square_wave_input.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using hil::EepromTimingMode;
using hil::kEepromWriteCycles;

constexpr uint8_t kEepeMask = 1U << hil::atmega328p::eecr_bit::kEepe;

struct Case1Writes {
    std::vector<hil::EepromWrite> writes;
    hil::EepromImage eeprom;
    hil::Cycles case_start_cycle = 0;  ///< cycle '1' was sent
    hil::Cycles busy_cycles_total = 0;
    bool busy_at_stop = false;
};

/// Boots the reference firmware, optionally starts square waves on pins 2 and
/// 3 (so the logged positions are not all zero), sends '1' and stops as the
/// `write_count`-th EEPROM write starts.
Case1Writes run_case1_until_writes(EepromTimingMode mode, std::size_t write_count,
                                   bool encoder_edges = true) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    hil::EepromWriteTiming timing(core, mode);
    hil::EepromPort eeprom(core);
    timing.set_listener([&](const hil::EepromWrite& /*w*/) {
        if (timing.writes().size() >= write_count) core.request_stop();
    });
    Case1Writes out;
    if (core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)) !=
        hil::RunStop::kCondition) {
        return out;
    }
    std::optional<SquareWaveInput> left, right;
    if (encoder_edges) {
        left.emplace(core, 'D', 2, 25'000);
        right.emplace(core, 'D', 3, 32'000);
    }
    out.case_start_cycle = core.cycle();
    uart.send("1");
    core.run_until(core.cycle() + hil::s_to_cycles(2.0, kUnoClockHz));
    out.writes = timing.writes();
    out.eeprom = eeprom.read_all();
    out.busy_cycles_total = timing.busy_cycles_total();
    out.busy_at_stop = timing.busy();
    return out;
}

TEST(EepromWriteTiming, WriteTimeIsTable8_2AtTheUnoClock) {
    // 26,368 RC-oscillator cycles at 8 MHz = 3.296 ms = 52,736 cycles at 16 MHz.
    EXPECT_EQ(kEepromWriteCycles, 52'736u);
    EXPECT_EQ(hil::eeprom_write_cycles(8'000'000), 26'368u);
    EXPECT_NEAR(hil::cycles_to_s(kEepromWriteCycles, kUnoClockHz), 3.296e-3, 1e-9);
}

TEST(EepromWriteTiming, DatasheetModeSpacesTheLogWritesByTheWriteTime) {
    // Three log calls: x at 0, 2, 4 and y at 500, 502, 504, in that order.
    // eeprom_write_byte polls EEPE before writing, so the y write of a call
    // starts once the x write's 52,736 cycles have passed (the poll loop is
    // SBIC + RJMP, 3 cycles; a timer-0 interrupt during the wait adds its
    // length). Calls are ~0.1 s apart, far more than one write.
    const auto run = run_case1_until_writes(EepromTimingMode::kDatasheet, 6);
    ASSERT_EQ(run.writes.size(), 6u);
    const uint16_t expected_addresses[] = {0, 500, 2, 502, 4, 504};
    for (std::size_t i = 0; i < run.writes.size(); ++i) {
        const auto& w = run.writes[i];
        EXPECT_EQ(w.address, expected_addresses[i]) << "write " << i;
        EXPECT_EQ(w.value, run.eeprom[w.address]) << "write " << i;  // what the EEPROM holds
        if (i > 0) {
            EXPECT_GE(w.cycle - run.writes[i - 1].cycle, kEepromWriteCycles) << "write " << i;
        }
    }
    for (std::size_t call = 0; call < 3; ++call) {
        const auto gap = run.writes[2 * call + 1].cycle - run.writes[2 * call].cycle;
        EXPECT_LT(gap, kEepromWriteCycles + 200) << "log call " << call;
    }
    // The robot moves in +x from the start (Theta = 0): x grows, ~0.3 m/s *
    // 0.1 s * 250 = ~7 counts per log call.
    EXPECT_GT(run.writes[4].value, run.writes[0].value);
    EXPECT_GT(run.writes[0].value, 0);
    // The sixth write was stopped as it started: five completed, one busy.
    EXPECT_TRUE(run.busy_at_stop);
    EXPECT_EQ(run.busy_cycles_total, 5 * kEepromWriteCycles);
}

TEST(EepromWriteTiming, InstantModeWritesXAndYBackToBack) {
    // simavr 1.6 clears EEPE at once: the y write follows the x write after
    // only int(Ey*250.0) (a float multiply and conversion) and the call.
    const auto run = run_case1_until_writes(EepromTimingMode::kInstant, 6);
    ASSERT_EQ(run.writes.size(), 6u);
    for (std::size_t call = 0; call < 3; ++call) {
        const auto gap = run.writes[2 * call + 1].cycle - run.writes[2 * call].cycle;
        EXPECT_LT(gap, kEepromWriteCycles / 20) << "log call " << call;
        EXPECT_EQ(run.writes[2 * call].address, 2 * call);
        EXPECT_EQ(run.writes[2 * call + 1].address, 500 + 2 * call);
    }
    EXPECT_EQ(run.busy_cycles_total, 0u);
    EXPECT_FALSE(run.busy_at_stop);
}

TEST(EepromWriteTiming, DatasheetModeLengthensTheLoggingBlockByOneWait) {
    // From one log call's x write to the next: 10 control iterations plus a
    // log call. delay(9) measures from its own start, so only the time the
    // firmware spends waiting on EEPE adds up: the y write waits for the x
    // write, i.e. 52,736 cycles minus the x-to-y time it takes anyway (the
    // instant-mode gap, 164 cycles measured). No encoder edges: the firmware
    // computes the same numbers in both modes.
    // What else differs is where delay()'s micros() polls fall against the
    // 1,024-cycle timer-0 period (the wait shifts the phase: 52,736 mod 1,024
    // = 512). Measured: lengthening 52,702 / 52,470 / 52,719 / 52,780 /
    // 52,572 cycles against 52,572 expected (within +-210); allowed: one
    // timer-0 period, 1,024 cycles (2 % of a write).
    constexpr std::size_t kCalls = 5;
    const auto ds = run_case1_until_writes(EepromTimingMode::kDatasheet, 2 * kCalls + 1, false);
    const auto in = run_case1_until_writes(EepromTimingMode::kInstant, 2 * kCalls + 1, false);
    ASSERT_EQ(ds.writes.size(), 2 * kCalls + 1);
    ASSERT_EQ(in.writes.size(), 2 * kCalls + 1);
    const auto block = [](const Case1Writes& r, std::size_t call) {
        return static_cast<int64_t>(r.writes[2 * call + 2].cycle - r.writes[2 * call].cycle);
    };
    const auto instant_gap = static_cast<int64_t>(in.writes[1].cycle - in.writes[0].cycle);
    EXPECT_LT(instant_gap, 1000);
    const auto expected = static_cast<int64_t>(kEepromWriteCycles) - instant_gap;
    double sum = 0;
    for (std::size_t call = 0; call < kCalls; ++call) {
        const int64_t lengthening = block(ds, call) - block(in, call);
        sum += static_cast<double>(lengthening);
        EXPECT_NEAR(static_cast<double>(lengthening), static_cast<double>(expected), 1024.0)
            << "log call " << call << ": instant block " << block(in, call) << " cycles";
    }
    // On average, one write time less the instant gap, to within the poll loop
    // exit (~12 cycles) and the phase jitter.
    EXPECT_NEAR(sum / kCalls, static_cast<double>(expected), 256.0);
}

TEST(EepromWriteTiming, EepeStaysSetForTheWriteTimeThenClears) {
    // Runs in 1,000-cycle steps until the first write starts, then checks EECR
    // as the firmware sees it: EEPE set until 52,736 cycles after the start,
    // clear after, and the y write starting as soon as it is clear.
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    hil::EepromWriteTiming timing(core);
    ASSERT_EQ(timing.mode(), EepromTimingMode::kDatasheet);
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)),
              hil::RunStop::kCondition);
    uart.send("1");
    const auto limit = core.cycle() + hil::s_to_cycles(0.5, kUnoClockHz);
    while (timing.writes().empty() && core.cycle() < limit) core.run_until(core.cycle() + 1000);
    ASSERT_EQ(timing.writes().size(), 1u);
    const auto start = timing.writes()[0].cycle;
    EXPECT_TRUE(timing.busy());
    EXPECT_NE(core.data(hil::atmega328p::reg::kEecr) & kEepeMask, 0);
    core.run_until(start + kEepromWriteCycles - 10);
    EXPECT_EQ(timing.writes().size(), 1u);  // y still waiting
    EXPECT_NE(core.data(hil::atmega328p::reg::kEecr) & kEepeMask, 0);
    core.run_until(start + kEepromWriteCycles + 200);
    ASSERT_EQ(timing.writes().size(), 2u);
    EXPECT_EQ(timing.writes()[1].address, 500);
    EXPECT_EQ(timing.busy_cycles_total(), kEepromWriteCycles);
}

}  // namespace
}  // namespace ddmr::test
