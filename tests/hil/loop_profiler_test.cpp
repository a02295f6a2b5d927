// LoopProfiler: exact loop cycle counts from the ELF's symbols alone.
#include "hil/loop_profiler.hpp"

#include <gtest/gtest.h>

#include "hil/uart_link.hpp"
#include "support/rig_run.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

TEST(CycleDistribution, HandWorkedValues) {
    // 1..100: min 1, max 100, mean 50.5; nearest-rank p99 = the 99th value = 99.
    std::vector<hil::Cycles> v;
    for (hil::Cycles i = 100; i >= 1; --i) v.push_back(i);
    const auto s = hil::cycle_distribution(v, 10);
    EXPECT_EQ(s.count, 100u);
    EXPECT_EQ(s.min, 1u);
    EXPECT_EQ(s.max, 100u);
    EXPECT_DOUBLE_EQ(s.mean, 50.5);
    EXPECT_EQ(s.p99, 99u);
    uint64_t total = 0;
    for (const auto b : s.bins) total += b;
    EXPECT_EQ(total, 100u);
    EXPECT_EQ(hil::cycle_distribution({}).count, 0u);
}

TEST(LoopProfiler, KnownLoopHasExactCycleCounts) {
    // tests/firmware/loop_fixture.c: main = 5 x NOP, CALL mark, RJMP;
    // mark = 3 x NOP, RET. Instruction set manual (ATmega328P, 16-bit PC):
    // NOP 1, CALL 4, RET 4, RJMP 2 cycles. From mark's return to its next
    // entry: RJMP + 5 NOP + CALL = 11; inside mark: 3 NOP + RET = 7; 18 in all.
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "loop_fixture.elf");
    hil::AvrCore core(elf);
    hil::LoopProfiler profiler(core, elf.require("mark"));
    profiler.arm();
    core.run_until(10'000);
    const auto& its = profiler.iterations();
    ASSERT_GT(its.size(), 500u);  // 10,000 cycles / 18 = 555 iterations
    for (const auto& it : its) {
        ASSERT_EQ(it.compute(), 11u);
        ASSERT_EQ(it.wait(), 7u);
        ASSERT_EQ(it.period(), 18u);
    }
}

TEST(LoopProfiler, ReferenceFirmwareCase1) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::RobotRig rig(elf, hil::RigConfig{});
    hil::LoopProfiler profiler(rig.core(), elf.require("delay"));
    ASSERT_EQ(rig.core().run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)), hil::RunStop::kCondition);
    profiler.arm();
    rig.uart().send("1");
    rig.core().run_until(rig.core().cycle() + hil::s_to_cycles(13.0, kUnoClockHz));
    std::vector<hil::Cycles> writes;
    for (const auto& w : rig.eeprom_timing().writes()) writes.push_back(w.cycle);
    profiler.tag_eeprom_writes(writes);
    const auto& its = profiler.iterations();
    // 1200 delay(9) calls; the first opens the first iteration: 1199 measured.
    ASSERT_EQ(its.size(), 1199u);
    std::size_t with_eeprom = 0;
    for (const auto& it : its) {
        // delay(9) waits until micros() has advanced 9000 us, polled in a
        // loop: at least 9 ms, and the poll's own period later at most.
        EXPECT_GE(it.wait(), hil::ms_to_cycles(9.0, kUnoClockHz));
        EXPECT_LT(it.wait(), hil::ms_to_cycles(9.03, kUnoClockHz));
        if (it.eeprom_write) {
            ++with_eeprom;
            // The log call's second write waits one programming time
            // (3.296 ms) for the first: compute is 3.3 to 3.4 ms longer.
            EXPECT_GT(it.compute(), hil::ms_to_cycles(1.0 + 3.296, kUnoClockHz));
        } else {
            // The control law in float on a 16 MHz AVR: about 1.1 ms (the
            // thesis quotes 0.8 ms); never near the 9 ms wait.
            EXPECT_GT(it.compute(), hil::ms_to_cycles(0.9, kUnoClockHz));
            EXPECT_LT(it.compute(), hil::ms_to_cycles(1.3, kUnoClockHz));
        }
    }
    // One log call per 10 iterations; the 120th follows the last delay.
    EXPECT_EQ(with_eeprom, 119u);
}

}  // namespace
}  // namespace ddmr::test
