// PinDriver: levels put on input pins now and at exact cycles. The firmware
// reads them (PINx), and an edge that its interrupt configuration catches
// starts the ISR at the edge's cycle as IsrMonitor measures it
// (tests/firmware/pins_fixture.c, edge_fixture.c).
#include "hil/pin_driver.hpp"

#include <gtest/gtest.h>

#include "hil/atmega328p.hpp"
#include "hil/isr_monitor.hpp"
#include "support/fixture_core.hpp"

namespace ddmr::test {
namespace {

namespace chip = hil::atmega328p;

constexpr int kPd7 = 7;
constexpr int kInt0Pin = 2;  // D2 = PD2 = INT0
constexpr int kA0 = 14;      // A0 = PC0 = PCINT8 (group 1)

/// pins_fixture: runs stage `s` and returns the PD7 level the firmware read.
uint8_t stage(FixtureCore& f, uint8_t s) {
    EXPECT_TRUE(f.handshake("stage", "done", s, 2000)) << "stage " << int{s};
    return f.u8("pin_read");
}

TEST(PinDriver, TheFirmwareReadsTheDrivenLevel) {
    FixtureCore f{"pins_fixture"};
    hil::PinDriver driver(f.core);
    EXPECT_EQ(stage(f, 1), 0);  // a floating input (simavr reads 0)
    driver.drive_now(kPd7, true);
    EXPECT_TRUE(driver.drives(kPd7));
    EXPECT_TRUE(driver.level(kPd7));
    EXPECT_EQ(stage(f, 7), 1);
}

TEST(PinDriver, ALowHoldsAgainstThePullUpThroughPortWrites) {
    // A pressed switch to GND on an INPUT_PULLUP pin reads LOW (section
    // 13.2.1; the 20-50 kOhm pull-up, 28.2, loses to the switch). Stage 8
    // writes PORTD twice (the pull-up again, then PD6): simavr 1.6 would
    // re-raise PD7 to 1 on each write without the driver's external level.
    FixtureCore f{"pins_fixture"};
    hil::PinDriver driver(f.core);
    EXPECT_EQ(stage(f, 2), 1);  // pull-up, nothing driving: high
    driver.drive_now(kPd7, false);
    EXPECT_EQ(stage(f, 8), 0);
}

TEST(PinDriver, ReleasedPinGoesBackToThePullUp) {
    FixtureCore f{"pins_fixture"};
    {
        hil::PinDriver driver(f.core);
        EXPECT_EQ(stage(f, 2), 1);
        driver.drive_now(kPd7, false);
        EXPECT_EQ(stage(f, 8), 0);
    }
    // The part is gone: the next PORTD write lets the pull-up win again.
    EXPECT_EQ(stage(f, 2), 1);
}

TEST(PinDriver, AResetKeepsTheDrivenLevel) {
    FixtureCore f{"pins_fixture"};
    hil::PinDriver driver(f.core);
    driver.drive_now(kPd7, true);
    driver.schedule(kPd7, f.core.cycle() + 5000, false);
    f.core.run_until(1000);
    f.core.reset();  // clears PIND and cancels every cycle timer
    EXPECT_TRUE(chip::bit_set(f.core.data(chip::reg::kPinD), 7));
    EXPECT_EQ(driver.pending(), 1u);
    f.core.run_until(6000);  // the queued edge still comes
    EXPECT_FALSE(chip::bit_set(f.core.data(chip::reg::kPinD), 7));
    EXPECT_EQ(driver.pending(), 0u);
}

TEST(PinDriver, RefusesAPinTheBoardHasNot) {
    FixtureCore f{"pins_fixture"};
    hil::PinDriver driver(f.core);
    expect_invalid_argument([&] { driver.schedule(42, 100, true); }, "no pin 42");
}

struct EdgeRig {
    FixtureCore f{"edge_fixture"};
    hil::IsrMonitor monitor{f.core, f.elf, hil::IsrMonitorConfig{false, 64}};
    hil::PinDriver driver{f.core};
    hil::Cycles t0 = 0;
    EdgeRig() {
        driver.drive_now(kInt0Pin, false);
        driver.drive_now(kA0, false);
        EXPECT_TRUE(f.run_until_u8("ready", 1, 5000));
        t0 = f.core.cycle() + 1000;  // in the NOP sled, interrupts on
    }
    const hil::IsrEvent* entry(int vector, std::size_t nth = 0) const {
        std::size_t seen = 0;
        for (const auto& e : monitor.events()) {
            if (e.vector == vector && seen++ == nth) return &e;
        }
        return nullptr;
    }
};

TEST(PinDriver, ScheduledInt0EdgeEntersTheIsrAtItsCycle) {
    // The datasheet (section 6.7.1): the response is 4 cycles minimum after
    // the flag is set and the instruction in progress completes; simavr 1.6
    // charges none (atmega328p::kDatasheetInterruptResponseCycles), so the
    // entry IsrMonitor measures is the edge's cycle itself, the chip's 4
    // cycles later.
    EdgeRig r;
    const hil::Cycles n = r.t0;
    r.driver.schedule(kInt0Pin, n, true);            // rising: INT0
    r.driver.schedule(kInt0Pin, n + 600, false);     // falling: no ISR (ISC0 = 11)
    r.driver.schedule(kInt0Pin, n + 1200, true);     // rising again
    r.f.core.run_until(n + 2000);
    EXPECT_EQ(r.f.u16("int0_count"), 2u);
    const hil::IsrEvent* first = r.entry(chip::vector::kInt0, 0);
    const hil::IsrEvent* second = r.entry(chip::vector::kInt0, 1);
    ASSERT_NE(first, nullptr);
    ASSERT_NE(second, nullptr);
    ASSERT_TRUE(first->raise_cycle.has_value());
    EXPECT_EQ(*first->raise_cycle, n);
    EXPECT_EQ(first->entry_cycle, n);
    EXPECT_EQ(first->entry_cycle + chip::kDatasheetInterruptResponseCycles, n + 4);  // the chip's entry
    EXPECT_EQ(second->entry_cycle, n + 1200);
}

TEST(PinDriver, EdgesScheduledOutOfOrderComeInCycleOrder) {
    EdgeRig r;
    const hil::Cycles n = r.t0;
    r.driver.schedule(kA0, n + 900, true);   // PCINT8: any change
    r.driver.schedule(kA0, n + 300, false);  // earlier, scheduled later: no change (already low)
    r.driver.schedule(kA0, n + 500, true);   // the first change
    r.f.core.run_until(n + 2000);
    // Changes at n + 500 (low -> high) only: n + 900 puts high on a high pin.
    EXPECT_EQ(r.f.u16("pcint1_count"), 1u);
    const hil::IsrEvent* e = r.entry(chip::vector::kPcint0 + 1);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->entry_cycle, n + 500);
    EXPECT_EQ(r.driver.pending(), 0u);
}

}  // namespace
}  // namespace ddmr::test
