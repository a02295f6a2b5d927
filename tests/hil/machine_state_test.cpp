// MachineState: capturing changes nothing in a run, TCNTn is what a read
// returns, and differences are named as the datasheet and the firmware
// name them.
#include "hil/machine_state.hpp"

#include <gtest/gtest.h>
#include <fmt/format.h>
#include <sim_avr.h>

#include "hil/data_objects.hpp"
#include "hil/mcu.hpp"
#include "hil/session.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::hil {
namespace {

SessionOptions options_for(double seconds) {
    SessionOptions o;
    o.time_limit = s_to_cycles(seconds, test::kUnoClockHz);
    return o;
}

// Two runs of the reference firmware stopped by the same timer every 5000
// cycles; one captures its state there: both end in the same state.
TEST(MachineState, CapturingChangesNothingInTheRun) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session with(elf, RigConfig{}, options_for(1.0));
    Session without(elf, RigConfig{}, options_for(1.0));
    int captures = 0;
    with.every(5000, [&](Cycles) {
        static_cast<void>(capture_machine_state(with.rig()));
        ++captures;
    });
    without.every(5000, [](Cycles) {});
    const Cycles end = s_to_cycles(0.3, test::kUnoClockHz);
    ASSERT_EQ(with.run(end), SessionStop::kReachedCycle);
    ASSERT_EQ(without.run(end), SessionStop::kReachedCycle);
    EXPECT_GT(captures, 900);
    const StateComparison c = compare_machine_states(capture_machine_state(with.rig()),
                                                     capture_machine_state(without.rig()), with.core().mcu(), nullptr);
    EXPECT_TRUE(c.equal()) << (c.shown.empty() ? "" : c.shown[0].what);
}

// Timer0 counts once per 64 cycles (the Arduino core's clk/64): between two
// captures d cycles apart (less than one 256-count wrap), TCNT0 moved by
// d / 64, give or take the count in progress; the stored byte is untouched.
TEST(MachineState, TimerCountIsWhatAReadReturnsNow) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session s(elf, RigConfig{}, options_for(1.0));
    const uint16_t tcnt0 = s.core().mcu().timers[0].tcnt_low;
    ASSERT_EQ(s.run(s_to_cycles(0.1, test::kUnoClockHz)), SessionStop::kReachedCycle);
    for (int i = 0; i < 20; ++i) {
        const uint8_t stored = s.core().raw()->data[tcnt0];
        const MachineState first = capture_machine_state(s.rig());
        EXPECT_EQ(s.core().raw()->data[tcnt0], stored);
        ASSERT_EQ(s.run(s.cycle() + 700 + 500 * static_cast<Cycles>(i)), SessionStop::kReachedCycle);
        const MachineState second = capture_machine_state(s.rig());
        const double counts = static_cast<double>(second.cycle - first.cycle) / 64.0;
        const auto moved = static_cast<uint8_t>(second.data[tcnt0] - first.data[tcnt0]);
        EXPECT_NEAR(moved, counts, 1.0) << "captures " << first.cycle << " and " << second.cycle;
    }
}

TEST(MachineState, DifferencesAreNamedAsTheDatasheetAndTheFirmwareNameThem) {
    const McuDescription& mcu = atmega328p_mcu();
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    const DataObjects objects(elf, mcu);
    ASSERT_GT(objects.size(), 0U);
    const DataObject& var = objects[0];
    MachineState a;
    a.data.assign(mcu.ram_end + 1U, 0);
    a.eeprom.assign(mcu.eeprom_bytes, 0xFF);
    MachineState b = a;
    b.pc = 0x2a4;
    b.data[24] = 0x13;
    b.data[mcu.sreg] = 0x80;
    b.data[mcu.timers[0].tcnt_low] = 0x42;
    b.data[var.address] = 1;
    b.eeprom[0x10] = 0x00;
    b.plant.x_m = 0.5;
    const StateComparison all = compare_machine_states(a, b, mcu, &objects);
    ASSERT_EQ(all.total, 7U);
    ASSERT_EQ(all.shown.size(), 7U);
    EXPECT_EQ(all.shown[0].what, "PC");
    EXPECT_EQ(all.shown[0].b, "0x02a4");
    EXPECT_EQ(all.shown[1].what, "r24");
    EXPECT_EQ(all.shown[1].a, "0x00");
    EXPECT_EQ(all.shown[1].b, "0x13");
    EXPECT_EQ(all.shown[2].what, "TCNT0");  // data space 0x46, before SREG's 0x5f
    EXPECT_EQ(all.shown[3].what, "SREG");
    EXPECT_EQ(all.shown[4].what, fmt::format("SRAM 0x{:04x} ({})", var.address, var.name));
    EXPECT_EQ(all.shown[5].what, "EEPROM 0x010");
    EXPECT_EQ(all.shown[6].what, "plant x_m");
    EXPECT_EQ(all.shown[6].b, "0.5");
    const StateComparison few = compare_machine_states(a, b, mcu, &objects, 2);
    EXPECT_EQ(few.total, 7U);
    EXPECT_EQ(few.shown.size(), 2U);
    EXPECT_TRUE(compare_machine_states(a, a, mcu, &objects).equal());
}

}  // namespace
}  // namespace ddmr::hil
