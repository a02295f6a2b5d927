// EncoderInjector: edges raised at their exact cycles start the firmware's
// INT0/INT1 ISRs; an edge that arrives while the previous one is pending is lost.
#include "hil/encoder_injector.hpp"

#include <gtest/gtest.h>

#include "hil/firmware_variables.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

struct Booted {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core{elf};
    hil::EncoderInjector injector{core, hil::uno_default_board()};
    hil::FirmwareVariables vars{elf, core};
    Booted() {
        // attachInterrupt(..., CHANGE) runs in setup(), before delay(5000).
        core.run_until(hil::s_to_cycles(0.5));
    }
};

TEST(EncoderInjector, EachEdgeRunsTheIsrOnceAfterItsCycle) {
    Booted b;
    const hil::Cycles start = b.core.cycle();
    bool level = false;
    for (int i = 1; i <= 20; ++i) {
        level = !level;
        b.injector.schedule(0, start + static_cast<hil::Cycles>(i) * 5000, level);
    }
    b.core.run_until(start + 21 * 5000);
    const auto& s = b.injector.stats(0);
    EXPECT_EQ(s.edges_injected, 20u);
    EXPECT_EQ(s.isr_count, 20u);
    EXPECT_EQ(s.lost_edges, 0u);
    EXPECT_EQ(b.vars.read_u32("Count1"), 20u);  // encoder1(): Count1++
    EXPECT_EQ(b.vars.read_u32("Count2"), 0u);
    // Each ISR starts after its edge and well before the next one. simavr
    // charges no interrupt-response cycles; the latency is the instruction
    // in progress (and a few cycles with interrupts off), not thousands.
    const auto& entries = b.injector.isr_entries(0);
    for (std::size_t i = 0; i < entries.size(); ++i) {
        const hil::Cycles edge = start + (i + 1) * 5000;
        EXPECT_GE(entries[i], edge) << i;
        EXPECT_LT(entries[i], edge + 200) << i;
    }
}

TEST(EncoderInjector, SecondEdgeWhileTheFirstIsPendingIsLost) {
    Booted b;
    const hil::Cycles c = b.core.cycle() + 1000;
    b.injector.schedule(1, c, true);
    b.injector.schedule(1, c, false);  // same cycle: INTF1 is still set
    b.core.run_until(c + 5000);
    const auto& s = b.injector.stats(1);
    EXPECT_EQ(s.edges_injected, 2u);
    EXPECT_EQ(s.lost_edges, 1u);
    EXPECT_EQ(s.isr_count, 1u);
    EXPECT_EQ(b.vars.read_u32("Count2"), 1u);
}

TEST(EncoderInjector, EncoderOnAPinWithoutInterruptCountsNoIsr) {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    auto board = hil::uno_default_board();
    board.encoder[0].pin = 4;
    hil::EncoderInjector injector(core, board);
    core.run_until(hil::s_to_cycles(0.5));
    injector.schedule(0, core.cycle() + 100, true);
    core.run_until(core.cycle() + 1000);
    EXPECT_FALSE(injector.interrupt_of(0).has_value());
    EXPECT_EQ(injector.stats(0).edges_injected, 1u);
    EXPECT_EQ(injector.stats(0).isr_count, 0u);
}

}  // namespace
}  // namespace ddmr::test
