// IsrMonitor: entry latency and duration of a hand-counted ISR are exact;
// precise mode accounts every cycle with SREG.I clear.
//
// isr_timing.elf (tests/isr/isr_timing.c), avr-objdump -d:
//   0x0004  jmp 0x80 <__vector_1>      3 cycles   (INT0 vector)
//   0x0080  nop x 5                    5 cycles   (__vector_1, ISR_NAKED)
//   0x008a  reti                       4 cycles
//   0x0096  rjmp .-2  (ff cf)          2 cycles   (main's for(;;))
// Duration (JMP to end of RETI) = 3 + 5 + 4 = 12 cycles. On the chip the
// interrupt response adds 4 more (datasheet 6.7.1: PC push and I clear before
// the JMP); simavr 1.6 charges none, so the HIL measures 12, not 16.
#include "hil/isr_monitor.hpp"

#include <gtest/gtest.h>

#include "hil/board.hpp"
#include "hil/encoder_injector.hpp"

namespace ddmr::test {
namespace {

constexpr uint16_t kRjmpSelf = 0xCFFF;        // rjmp .-2
constexpr hil::Cycles kIsrCycles = 3 + 5 + 4;  // jmp + 5 nop + reti
constexpr hil::Cycles kRjmpCycles = 2;

struct TimingBench {
    hil::ElfImage elf = hil::ElfImage::read(std::string(DDMR_ISR_FIRMWARE_DIR) + "/isr_timing.elf");
    hil::AvrCore core{elf};
    hil::EncoderInjector injector{core, hil::default_board()};
    hil::Cycles loop_start = 0;  ///< an instruction boundary of the rjmp loop

    TimingBench() {
        elf.require_mcu(hil::atmega328p_mcu());
        // Single-step to the first "rjmp .-2": from here on every instruction
        // boundary is loop_start + 2k and I is set (sei ran before).
        const auto stop = core.run_until(100'000, [&] { return core.flash_word(core.pc()) == kRjmpSelf; });
        if (stop != hil::RunStop::kCondition) throw std::runtime_error("isr_timing never reached its loop");
        loop_start = core.cycle();
    }
};

TEST(IsrMonitor, DurationIsTheHandCountedCyclesAndLatencyIsExact) {
    TimingBench b;
    hil::IsrMonitor monitor(b.core, b.elf, {false, 16});
    const hil::Cycles c0 = b.loop_start;
    // Edge 1 on an instruction boundary: raised there, taken at once (I set,
    // nothing pending, no response cycles in simavr): latency 0.
    b.injector.schedule(0, c0 + 1000, true);
    // Edge 2 one cycle into an rjmp: simavr serves cycle timers after the
    // instruction, so the pin (and PENDING) rise at the next boundary, c0 + 2002;
    // latency from PENDING 0, from the injection 1.
    b.injector.schedule(0, c0 + 2001, false);
    b.core.run_until(c0 + 3000);

    const auto& ev = monitor.events();
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_EQ(ev[0].vector, hil::atmega328p::vector::kInt0);
    EXPECT_EQ(ev[0].raise_cycle, c0 + 1000);
    EXPECT_EQ(ev[0].entry_cycle, c0 + 1000);
    EXPECT_EQ(ev[0].exit_cycle, c0 + 1000 + kIsrCycles);
    EXPECT_EQ(ev[1].raise_cycle, c0 + 2002);  // the INT0 PENDING rise = the pin edge's cycle
    EXPECT_EQ(ev[1].entry_cycle, c0 + 2002);
    EXPECT_EQ(ev[1].entry_cycle - (c0 + 2001), 1u);  // latency from the scheduled injection
    // The EncoderInjector sees the same entries.
    EXPECT_EQ(b.injector.isr_entries(0), (std::vector<hil::Cycles>{c0 + 1000, c0 + 2002}));

    const auto s = monitor.summary();
    ASSERT_EQ(s.vectors.size(), 1u);
    const auto& v = s.vectors[0];
    EXPECT_EQ(v.name, "INT0");
    EXPECT_EQ(v.handler, "__vector_1");
    EXPECT_EQ(v.count, 2u);
    EXPECT_EQ(v.raised, 2u);
    EXPECT_EQ(v.latency.count, 2u);
    EXPECT_EQ(v.latency.max, 0u);
    EXPECT_EQ(v.duration.min, kIsrCycles);
    EXPECT_EQ(v.duration.max, kIsrCycles);
    EXPECT_DOUBLE_EQ(v.duration.mean(), 12.0);
    EXPECT_EQ(v.duration_histogram.counts[hil::CycleHistogram::bin_of(12)], 2u);  // bin 8-15
    EXPECT_EQ(v.latency_histogram.counts[0], 2u);
    EXPECT_EQ(s.isr_cycles, 2 * kIsrCycles);
    EXPECT_DOUBLE_EQ(v.cpu_share, static_cast<double>(2 * kIsrCycles) / static_cast<double>(s.observed_cycles()));
    EXPECT_FALSE(s.interrupts_disabled_cycles.has_value());  // not precise
    EXPECT_EQ(s.max_nesting, 1);
}

TEST(IsrMonitor, EdgeDuringTheIsrWaitsForRetiAndTwoInstructions) {
    TimingBench b;
    hil::IsrMonitor monitor(b.core, b.elf, {false, 16});
    const hil::Cycles e = b.loop_start + 1000;
    b.injector.schedule(0, e, true);
    // Inside the handler (its JMP ends at e + 3, the NOPs run e+3..e+8):
    // raised at e + 4 with I clear, so it waits. RETI ends at e + 12. simavr
    // then runs two instructions (2 x rjmp, 4 cycles) before it takes the
    // pending interrupt (interrupt_state -2 after RETI; the datasheet runs
    // one instruction, then 4 response cycles): entry at e + 16.
    b.injector.schedule(0, e + 4, false);
    b.core.run_until(e + 1000);
    const auto& ev = monitor.events();
    ASSERT_EQ(ev.size(), 2u);
    EXPECT_EQ(ev[1].raise_cycle, e + 4);
    EXPECT_EQ(ev[1].entry_cycle, e + kIsrCycles + 2 * kRjmpCycles);
    const auto v = monitor.summary().vectors.at(0);
    EXPECT_EQ(v.latency.min, 0u);
    EXPECT_EQ(v.latency.max, kIsrCycles + 2 * kRjmpCycles - 4);  // 12
    EXPECT_EQ(b.injector.stats(0).lost_edges, 0u);
}

TEST(IsrMonitor, PreciseModeCountsCyclesWithInterruptsDisabled) {
    TimingBench b;
    hil::IsrMonitor precise(b.core, b.elf, {true, 0});
    const hil::Cycles c0 = b.loop_start;
    for (int i = 1; i <= 10; ++i) b.injector.schedule(0, c0 + 500 * static_cast<hil::Cycles>(i), (i % 2) != 0);
    b.core.run_until(c0 + 6000);
    const auto s = precise.summary();
    // The loop never clears I: the only cycles with I clear are the ISRs'
    // (I is cleared at entry and set by RETI, whose 4 cycles count as disabled).
    ASSERT_TRUE(s.interrupts_disabled_cycles.has_value());
    EXPECT_EQ(*s.interrupts_disabled_cycles, 10 * kIsrCycles);
    EXPECT_EQ(s.isr_cycles, 10 * kIsrCycles);
    EXPECT_EQ(s.vectors.at(0).count, 10u);
}

TEST(IsrMonitor, HistogramBinsArePowersOfTwo) {
    using H = hil::CycleHistogram;
    EXPECT_EQ(H::bin_of(0), 0u);
    EXPECT_EQ(H::bin_of(1), 1u);
    EXPECT_EQ(H::bin_of(2), 2u);
    EXPECT_EQ(H::bin_of(3), 2u);
    EXPECT_EQ(H::bin_of(12), 4u);
    EXPECT_EQ(H::bin_of(65535), 16u);
    EXPECT_EQ(H::bin_of(65536), 17u);
    EXPECT_EQ(H::bin_of(uint64_t{1} << 40), 17u);
    EXPECT_EQ(H::label(4), "8-15");
    EXPECT_EQ(H::label(17), ">=65536");
    for (std::size_t bin = 1; bin < H::kBins; ++bin) EXPECT_EQ(H::bin_of(H::lower_bound(bin)), bin);
}

TEST(IsrMonitor, MarkdownHasOneRowPerVector) {
    TimingBench b;
    hil::IsrMonitor monitor(b.core, b.elf);
    b.injector.schedule(0, b.loop_start + 100, true);
    b.core.run_until(b.loop_start + 1000);
    const std::string md = hil::to_markdown(monitor.summary());
    EXPECT_NE(md.find("| 1 | INT0 | `__vector_1` | 1 | 0 / 0.0 / 0 | 12 / 12.0 / 12 |"), std::string::npos) << md;
    EXPECT_NE(md.find("| INT0 | duration | 8-15: 1 |"), std::string::npos) << md;
}

}  // namespace
}  // namespace ddmr::test
