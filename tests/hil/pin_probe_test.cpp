// PinProbe: a pin's mode, pull-up and the level a part sees, as ATmega328P
// datasheet 7810D section 13.2.1 Table 13-1 defines them, followed through
// the firmware's own register writes (tests/firmware/pins_fixture.c).
#include "hil/pin_probe.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "support/fixture_core.hpp"

namespace ddmr::test {
namespace {

constexpr int kPin = 7;  // PD7 on the Uno
constexpr hil::Cycles kStageCycles = 2000;

struct Event {
    hil::PinState state;
    hil::Cycles cycle;
};

struct Probed {
    FixtureCore f{"pins_fixture"};
    hil::PinProbe probe{f.core, kPin};
    std::vector<Event> events;
    Probed() {
        probe.set_listener([this](const hil::PinState& s, hil::Cycles c) { events.push_back({s, c}); });
    }
    /// Runs fixture stage `s`; returns the level the firmware read on PD7.
    uint8_t stage(uint8_t s) {
        EXPECT_TRUE(f.handshake("stage", "done", s, kStageCycles)) << "stage " << int{s};
        return f.u8("pin_read");
    }
};

TEST(PinState, Table13_1) {
    using hil::PinLevel;
    // DDxn PORTxn PUD -> pull-up, level
    EXPECT_EQ(hil::pin_state(false, false, false).level, PinLevel::floating);
    EXPECT_EQ(hil::pin_state(false, true, false).level, PinLevel::pulled_up);
    EXPECT_TRUE(hil::pin_state(false, true, false).pull_up);
    EXPECT_EQ(hil::pin_state(false, true, true).level, PinLevel::floating);
    EXPECT_FALSE(hil::pin_state(false, true, true).pull_up);
    EXPECT_EQ(hil::pin_state(true, false, true).level, PinLevel::driven_low);
    EXPECT_EQ(hil::pin_state(true, true, true).level, PinLevel::driven_high);
    EXPECT_FALSE(hil::pin_state(true, true, false).pull_up);  // an output has no pull-up
}

TEST(PinProbe, AfterResetEveryPinIsAFloatingInput) {
    FixtureCore f{"pins_fixture"};
    hil::PinProbe probe(f.core, kPin);
    // Section 13.2.1: "The port pins are tri-stated when a reset condition becomes active".
    EXPECT_FALSE(probe.state().output);
    EXPECT_EQ(probe.state().level, hil::PinLevel::floating);
    EXPECT_EQ(probe.pin(), kPin);
}

TEST(PinProbe, PullUpOnAndNoDriverReadsHighAndPudMakesItFloat) {
    Probed p;
    EXPECT_EQ(p.stage(1), 0);
    EXPECT_EQ(p.probe.state().level, hil::PinLevel::floating);
    EXPECT_TRUE(p.events.empty());  // nothing changed: still the reset state

    // INPUT_PULLUP with nothing connected: the part sees the pull-up, and
    // so does the firmware (PIND7 = 1).
    EXPECT_EQ(p.stage(2), 1);
    ASSERT_EQ(p.events.size(), 1u);
    EXPECT_EQ(p.events[0].state.level, hil::PinLevel::pulled_up);
    EXPECT_TRUE(p.events[0].state.pull_up);
    EXPECT_TRUE(p.events[0].state.port_bit);

    // PUD = 1 in MCUCR: the pull-up is off although PORTD7 is still 1.
    p.stage(3);
    ASSERT_EQ(p.events.size(), 2u);
    EXPECT_EQ(p.events[1].state.level, hil::PinLevel::floating);
    EXPECT_TRUE(p.events[1].state.port_bit);
    EXPECT_FALSE(p.events[1].state.pull_up);

    p.stage(4);
    ASSERT_EQ(p.events.size(), 3u);
    EXPECT_EQ(p.events[2].state.level, hil::PinLevel::pulled_up);
}

TEST(PinProbe, OutputLevelsFollowPortAndPinToggle) {
    Probed p;
    p.stage(1);
    // Stage 5 writes PORTD7 = 1 (pull-up on: one change), then DDRD7 = 1.
    EXPECT_EQ(p.stage(5), 1);
    ASSERT_EQ(p.events.size(), 2u);
    EXPECT_EQ(p.events[0].state.level, hil::PinLevel::pulled_up);
    EXPECT_EQ(p.events[1].state.level, hil::PinLevel::driven_high);
    EXPECT_TRUE(p.events[1].state.output);
    EXPECT_LT(p.events[0].cycle, p.events[1].cycle);
    // Writing 1 to PIND7 toggles PORTD7 (section 13.2.2): driven low.
    EXPECT_EQ(p.stage(6), 0);
    ASSERT_EQ(p.events.size(), 3u);
    EXPECT_EQ(p.events[2].state.level, hil::PinLevel::driven_low);
    // Back to an input with PORTD7 = 0: floating.
    p.stage(7);
    ASSERT_EQ(p.events.size(), 4u);
    EXPECT_EQ(p.events[3].state.level, hil::PinLevel::floating);
    EXPECT_FALSE(p.events[3].state.output);
    EXPECT_EQ(p.probe.changes(), 4u);
}

TEST(PinProbe, ResetIsAChangeBackToFloating) {
    Probed p;
    p.stage(5);
    const std::size_t before = p.events.size();
    p.f.core.reset();
    ASSERT_EQ(p.events.size(), before + 1);
    EXPECT_EQ(p.events.back().state.level, hil::PinLevel::floating);
}

TEST(PinProbe, RefusesAPinTheBoardHasNot) {
    FixtureCore f{"pins_fixture"};
    expect_invalid_argument([&] { hil::PinProbe probe(f.core, 20); }, "no pin 20");
}

}  // namespace
}  // namespace ddmr::test
