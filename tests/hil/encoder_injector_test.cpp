// EncoderInjector: edges raised at their exact cycles start the firmware's
// INT0/INT1 ISRs; an edge that arrives while the previous one is pending is lost.
#include "hil/encoder_injector.hpp"

#include <gtest/gtest.h>

#include "hil/atmega328p.hpp"
#include "hil/firmware_variables.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

struct Booted {
    hil::ElfImage elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core{elf};
    hil::EncoderInjector injector{core, hil::default_board()};
    hil::FirmwareVariables vars{elf, core};
    Booted() {
        // attachInterrupt(..., CHANGE) runs in setup(), before delay(5000).
        core.run_until(hil::s_to_cycles(0.5, kUnoClockHz));
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
    auto board = hil::default_board();
    board.wheel[0].encoder.pin[0] = 4;
    hil::EncoderInjector injector(core, board);
    core.run_until(hil::s_to_cycles(0.5, kUnoClockHz));
    injector.schedule(0, core.cycle() + 100, true);
    core.run_until(core.cycle() + 1000);
    EXPECT_FALSE(injector.interrupt_of(0).has_value());
    EXPECT_EQ(injector.stats(0).edges_injected, 1u);
    EXPECT_EQ(injector.stats(0).isr_count, 0u);
}


/// The fixture's board: right wheel quadrature A = D2 (INT0), B = D4; left
/// wheel quadrature on A4 / A5 (pin-change group 1).
hil::BoardWiring fixture_board() {
    hil::BoardWiring b = hil::default_board();
    b.wheel[0].encoder.kind = hil::EncoderKind::quadrature;
    b.wheel[0].encoder.pin = {2, 4};
    b.wheel[1].encoder.kind = hil::EncoderKind::quadrature;
    b.wheel[1].encoder.pin = {18, 19};
    return b;
}

struct Fixture {
    hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "encoder_fixture.elf");
    hil::AvrCore core{elf};
    hil::EncoderInjector injector{core, fixture_board()};
    hil::FirmwareVariables vars{elf, core};
    Fixture() {
        core.run_until(2000);  // main() has configured the interrupts
        EXPECT_EQ(u8("ready"), 1u);
    }
    uint32_t u16(const char* name) { return static_cast<uint32_t>(vars.read(name, hil::VarType::kUint16)); }
    uint32_t u8(const char* name) { return static_cast<uint32_t>(vars.read(name, hil::VarType::kUint8)); }
};

TEST(EncoderInjector, RisingSenseRunsTheIsrOnRisingEdgesOnlyAndReadsBsTrueLevel) {
    Fixture f;
    const hil::Cycles t0 = f.core.cycle();
    // Quadrature forward: A rises with B low, B rises, A falls, B falls: the
    // ISR (A rising) sees B low. Then backwards: B rises, A rises (B high).
    f.injector.schedule(0, 0, t0 + 1000, true);   // A up   (B low)
    f.injector.schedule(0, 1, t0 + 2000, true);   // B up
    f.injector.schedule(0, 0, t0 + 3000, false);  // A down: no ISR on RISING
    f.injector.schedule(0, 1, t0 + 4000, false);  // B down
    f.injector.schedule(0, 1, t0 + 5000, true);   // reverse: B up first
    f.injector.schedule(0, 0, t0 + 6000, true);   // A up   (B high)
    f.core.run_until(t0 + 8000);
    EXPECT_EQ(f.u16("int0_count"), 2u);
    EXPECT_EQ(f.u16("b_high_count"), 1u);
    const auto& s = f.injector.stats(0);
    EXPECT_EQ(s.edges_injected, 6u);
    EXPECT_EQ(s.isr_count, 2u);
    EXPECT_EQ(s.lost_edges, 0u) << (s.last_lost_cycle ? *s.last_lost_cycle - t0 : 0);
    // Each ISR starts at or just after its edge (simavr charges no response cycles).
    ASSERT_EQ(f.injector.isr_entries(0).size(), 2u);
    EXPECT_GE(f.injector.isr_entries(0)[0], t0 + 1000);
    EXPECT_LT(f.injector.isr_entries(0)[0], t0 + 1000 + 20);
    EXPECT_GE(f.injector.isr_entries(0)[1], t0 + 6000);
    EXPECT_LT(f.injector.isr_entries(0)[1], t0 + 6000 + 20);
}

TEST(EncoderInjector, PinChangeInterruptEntersAtTheEdgeAndMergesAPendingChange) {
    Fixture f;
    const hil::Cycles t0 = f.core.cycle();
    EXPECT_EQ(f.injector.vector_of(1), hil::atmega328p::vector::kPcint0 + 1);
    f.injector.schedule(1, 0, t0 + 1000, true);  // A4 up: PCINT1
    f.core.run_until(t0 + 1500);
    EXPECT_EQ(f.u16("pcint1_count"), 1u);
    EXPECT_EQ(f.u8("last_pinc") & 0x30U, 0x10U);  // A4 high, A5 low in the ISR
    ASSERT_EQ(f.injector.isr_entries(1).size(), 1u);
    EXPECT_GE(f.injector.isr_entries(1)[0], t0 + 1000);
    EXPECT_LT(f.injector.isr_entries(1)[0], t0 + 1000 + 20);
    // A5 and A4 change at the same cycle: one PCIF1 request, one ISR; the
    // second change finds the flag set: lost as a separate interrupt.
    f.injector.schedule(1, 1, t0 + 2000, true);
    f.injector.schedule(1, 0, t0 + 2000, false);
    f.core.run_until(t0 + 3000);
    EXPECT_EQ(f.u16("pcint1_count"), 2u);
    EXPECT_EQ(f.injector.stats(1).lost_edges, 1u);
    EXPECT_EQ(f.u8("last_pinc") & 0x30U, 0x20U);  // the ISR reads both pins' new levels
}

TEST(EncoderInjector, TimerPwmOnAPinOfTheSameGroupRaisesNoPinChangeInterrupt) {
    // Timer0 drives OC0B = D5 (port D, PCINT21, not in PCMSK2) at 976.6 Hz;
    // only D4 (PCINT20) is in the mask. 0.1 s = ~98 PWM periods without an
    // encoder edge: no PCINT2; then one edge on D4: exactly one.
    Fixture f;
    const hil::Cycles t0 = f.core.cycle();
    f.core.run_until(t0 + hil::s_to_cycles(0.1, kUnoClockHz));
    EXPECT_EQ(f.u16("pcint2_count"), 0u);
    const hil::Cycles t1 = f.core.cycle();
    f.injector.schedule(0, 1, t1 + 1000, true);  // the right wheel's B channel is D4
    f.core.run_until(t1 + 3000);
    EXPECT_EQ(f.u16("pcint2_count"), 1u);
}

TEST(EncoderInjector, ReversedQuadratureSwapsTheChannelsOntoThePins) {
    hil::BoardWiring b = fixture_board();
    b.wheel[0].encoder.reversed = true;
    hil::ElfImage elf = hil::ElfImage::read(test_firmware_dir() / "encoder_fixture.elf");
    hil::AvrCore core{elf};
    hil::EncoderInjector injector{core, b};
    injector.drive_now(0, 0, true);   // the plant's A ...
    injector.drive_now(0, 1, false);  // ... and B
    EXPECT_FALSE(injector.level(0, 0));  // board pin A (D2) carries the plant's B
    EXPECT_TRUE(injector.level(0, 1));   // board pin B (D4) the plant's A
}

}  // namespace
}  // namespace ddmr::test
