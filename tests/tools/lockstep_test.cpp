// Lockstep: two threads meet at checkpoints; the first that differs is kept
// with the last equal one, a run that ends first is a difference, and no
// side waits once they differ (the tests would hang).
#include "lockstep.hpp"

#include <gtest/gtest.h>

#include <thread>
#include <vector>

#include "hil/mcu.hpp"

namespace ddmr::tools {
namespace {

using hil::MachineState;

MachineState state_at(hil::Cycles cycle, uint8_t r24 = 0) {
    MachineState s;
    s.cycle = cycle;
    s.pc = 0x100;
    s.data.assign(hil::atmega328p_mcu().ram_end + 1U, 0);
    s.data[24] = r24;
    s.eeprom.assign(1024, 0xFF);
    return s;
}

/// Runs `a` and `b` (checkpoints, then an end) on two threads.
void run_sides(Lockstep& l, const std::vector<MachineState>& a, const std::vector<MachineState>& b) {
    const auto side = [&l](Lockstep::Side s, const std::vector<MachineState>& states) {
        for (std::size_t i = 0; i + 1 < states.size(); ++i) l.checkpoint(s, states[i]);
        l.ended(s, states.back());
    };
    std::thread t([&] { side(Lockstep::kB, b); });
    side(Lockstep::kA, a);
    t.join();
}

TEST(Lockstep, EqualRunsCountEveryCheckpointAndTheirEnd) {
    Lockstep l(hil::atmega328p_mcu(), nullptr);
    const std::vector<MachineState> run = {state_at(1000), state_at(2000), state_at(3000), state_at(3500)};
    run_sides(l, run, run);
    EXPECT_FALSE(l.divergence().has_value());
    EXPECT_EQ(l.checkpoints_equal(), 4U);  // three checkpoints and the end
    EXPECT_EQ(l.last_equal_cycle(), 3500U);
}

TEST(Lockstep, KeepsTheFirstCheckpointThatDiffersWithTheLastEqualOne) {
    Lockstep l(hil::atmega328p_mcu(), nullptr);
    const std::vector<MachineState> a = {state_at(1000), state_at(2000), state_at(3000, 7), state_at(4000, 9),
                                         state_at(5000)};
    const std::vector<MachineState> b = {state_at(1000), state_at(2000), state_at(3000, 8), state_at(4000, 1),
                                         state_at(5000)};
    run_sides(l, a, b);
    const std::optional<LockstepDivergence> found = l.divergence();
    ASSERT_TRUE(found.has_value());
    const LockstepDivergence& d = *found;
    EXPECT_EQ(d.last_equal_cycle, 2000U);
    EXPECT_EQ(d.a.cycle, 3000U);
    ASSERT_EQ(d.comparison.total, 1U);
    EXPECT_EQ(d.comparison.shown[0].what, "r24");
    EXPECT_EQ(d.comparison.shown[0].a, "0x07");
    EXPECT_EQ(d.comparison.shown[0].b, "0x08");
    EXPECT_EQ(l.checkpoints_equal(), 2U);  // none counted after the difference
}

TEST(Lockstep, ARunThatEndsWhileTheOtherGoesOnIsADifference) {
    Lockstep l(hil::atmega328p_mcu(), nullptr);
    const std::vector<MachineState> a = {state_at(1000), state_at(2000)};  // ends at 2000
    const std::vector<MachineState> b = {state_at(1000), state_at(2000), state_at(3000), state_at(3100)};
    run_sides(l, a, b);
    const std::optional<LockstepDivergence> found = l.divergence();
    ASSERT_TRUE(found.has_value());
    const LockstepDivergence& d = *found;
    EXPECT_EQ(d.last_equal_cycle, 1000U);
    EXPECT_TRUE(d.a_ended);
    EXPECT_FALSE(d.b_ended);
    ASSERT_FALSE(d.comparison.shown.empty());
    EXPECT_EQ(d.comparison.shown[0].what, "the run");
    EXPECT_EQ(d.comparison.shown[0].a, "ended");
    EXPECT_EQ(d.comparison.shown[0].b, "goes on");
}

TEST(Lockstep, ASideAbandonedAfterAnErrorReleasesTheOther) {
    Lockstep l(hil::atmega328p_mcu(), nullptr);
    std::thread t([&] { l.ended(Lockstep::kB, std::nullopt); });
    l.checkpoint(Lockstep::kA, state_at(1000));  // returns: B will never come
    t.join();
    l.checkpoint(Lockstep::kA, state_at(2000));
    EXPECT_FALSE(l.divergence().has_value());
    EXPECT_EQ(l.checkpoints_equal(), 0U);
}

}  // namespace
}  // namespace ddmr::tools
