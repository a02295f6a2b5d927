// ResetMonitor (issue 32): restarts from address 0 the firmware did not ask
// for are counted, the first is told with the PC it came from, and more than
// ten within one simulated second stop the run. Power-on and AvrCore::reset()
// (the watchdog's path) are asked for: never counted.
#include "hil/reset_monitor.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include <sim_avr.h>
#include <sim_io.h>

#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using hil::Cycles;
using hil::ResetRate;

constexpr Cycles kSecond = kUnoClockHz;

TEST(ResetRate, TenRestartsWithinASecondGoOnTheEleventhStops) {
    ResetRate rate(kSecond);
    for (Cycles k = 0; k < 10; ++k) EXPECT_FALSE(rate.note(1000 + k * 1000)) << k;
    EXPECT_TRUE(rate.note(11'000));
    EXPECT_EQ(rate.count(), 11U);
}

TEST(ResetRate, ElevenRestartsSpanningASecondAreNoLoop) {
    // Every 0.1 s: restarts 0 and 10 are exactly one second apart (not within it).
    ResetRate rate(kSecond);
    for (Cycles k = 0; k <= 10; ++k) EXPECT_FALSE(rate.note(k * kSecond / 10)) << k;
    // The 12th, 0.05 s later: restarts 1..11 span 0.95 s.
    EXPECT_TRUE(rate.note(10 * kSecond / 10 + kSecond / 20));
}

TEST(ResetRate, OnlyTheLastElevenCount) {
    // A slow stretch first, then ten quick ones: the window slides.
    ResetRate rate(kSecond);
    for (Cycles k = 0; k < 5; ++k) EXPECT_FALSE(rate.note(k * 2 * kSecond));
    const Cycles t0 = 20 * kSecond;
    for (Cycles k = 0; k < 10; ++k) EXPECT_FALSE(rate.note(t0 + k)) << k;
    EXPECT_TRUE(rate.note(t0 + 10));
}

/// A core on one of tests/firmware's weak_call_fixture builds, its monitor's
/// warnings collected.
struct Monitored {
    explicit Monitored(const std::string& elf_name)
        : elf(hil::ElfImage::read(test_firmware_dir() / elf_name)), core(elf), monitor(core) {
        monitor.set_warning_sink([this](const std::string& line) { warnings.push_back(line); });
    }
    hil::ElfImage elf;
    hil::AvrCore core;
    hil::ResetMonitor monitor;
    std::vector<std::string> warnings;
};

TEST(ResetMonitor, WatchesTheStartUpsSregWrite) {
    // avr-libc's .init2 at __ctors_end: `clr r1; out SREG, r1`.
    const Monitored m("weak_call_fixture_guarded.elf");
    ASSERT_TRUE(m.monitor.watching());
    EXPECT_EQ(*m.monitor.startup_pc(), m.elf.require("__ctors_end").address + 2);
}

TEST(ResetMonitor, PowerOnAndAResetAreNotCounted) {
    Monitored m("weak_call_fixture_guarded.elf");  // tests the weak hook: never calls 0
    EXPECT_EQ(m.core.run_until(100'000), hil::RunStop::kReachedCycle);
    m.core.reset();  // as the watchdog does
    EXPECT_EQ(m.core.run_until(200'000), hil::RunStop::kReachedCycle);
    m.core.reset();
    m.core.reset();  // twice before the start-up code runs: still one start
    EXPECT_EQ(m.core.run_until(300'000), hil::RunStop::kReachedCycle);
    EXPECT_EQ(m.monitor.count(), 0U);
    EXPECT_FALSE(m.monitor.first());
    EXPECT_FALSE(m.monitor.loop());
    EXPECT_TRUE(m.warnings.empty());
}

TEST(ResetMonitor, ACallToZeroIsCountedAndALoopStopsTheRun) {
    // main's first instruction is `call 0`: a restart every few dozen cycles.
    Monitored m("weak_call_fixture_unguarded.elf");
    const uint32_t main_pc = m.elf.require("main").address;
    EXPECT_EQ(m.core.run_until(kSecond), hil::RunStop::kCondition);  // the monitor stopped it
    EXPECT_LT(m.core.cycle(), kSecond / 100);
    ASSERT_TRUE(m.monitor.loop());
    EXPECT_EQ(m.monitor.loop()->count, 11U);
    // The stop comes after the current instruction batch: maybe a few more restarts.
    EXPECT_GE(m.monitor.count(), 11U);
    ASSERT_TRUE(m.monitor.first());
    const std::string from = fmt::format("`call 0` at PC 0x{:04x} in main", main_pc);
    EXPECT_EQ(m.monitor.first()->from, from);
    EXPECT_EQ(m.monitor.loop()->first_from, from);
    // SP then: the start-up's `call main` and main's `call 0` each pushed a return address.
    EXPECT_EQ(m.monitor.first()->sp, m.core.mcu().ram_end - 2 * m.core.mcu().pc_bytes);
    ASSERT_EQ(m.warnings.size(), 1U);  // the first only
    EXPECT_NE(m.warnings[0].find("the firmware restarted from address 0 without a reset at cycle "), std::string::npos);
    EXPECT_NE(m.warnings[0].find(from), std::string::npos) << m.warnings[0];
}

TEST(ResetMonitor, ANullFunctionPointerIsAnIcallWithZeroZ) {
    Monitored m("weak_call_fixture_null_pointer.elf");
    m.core.run_until(kSecond);
    ASSERT_TRUE(m.monitor.first());
    const std::string& from = m.monitor.first()->from;
    EXPECT_EQ(from.rfind("`icall` with Z = 0 (a null function pointer) at PC 0x", 0), 0U) << from;
    EXPECT_NE(from.find(" in main"), std::string::npos) << from;
    EXPECT_TRUE(m.monitor.loop());
}

/// Another writer of SREG, as a part could be: counts the firmware's SREG writes.
void count_sreg_write(avr_t* avr, uint16_t address, uint8_t value, void* param) {
    avr->data[address] = value;
    ++*static_cast<uint64_t*>(param);
}

TEST(ResetMonitor, LeavesNoCallbackBehindAlongsideAnotherWriter) {
    // The call-0 fixture writes SREG at every restart. A monitor destroyed
    // before the run must not be called (under the sanitizers: no use after
    // free), and simavr's dispatcher keeps the other writer working.
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "weak_call_fixture_unguarded.elf");
    for (const bool other_writer : {false, true}) {
        hil::AvrCore core(elf);
        uint64_t writes = 0;
        if (other_writer) avr_register_io_write(core.raw(), core.mcu().sreg, &count_sreg_write, &writes);
        { const hil::ResetMonitor gone(core); }
        // Nothing of it is left in simavr: no callback, or only the other writer's.
        const auto& slot = core.raw()->io[AVR_DATA_TO_IO(core.mcu().sreg)].w;
        if (other_writer) {
            const auto& shared = core.raw()->io_shared_io[reinterpret_cast<intptr_t>(slot.param)];
            int live = 0;
            for (int i = 0; i < shared.used; ++i) live += shared.io[i].c != nullptr ? 1 : 0;
            EXPECT_EQ(live, 1);
        } else {
            EXPECT_EQ(slot.c, nullptr);
        }
        hil::ResetMonitor monitor(core);
        EXPECT_EQ(core.run_until(kSecond), hil::RunStop::kCondition) << other_writer;  // the live one stops it
        EXPECT_TRUE(monitor.loop()) << other_writer;
        if (other_writer) {
            EXPECT_GE(writes, 12U);  // power-on and each restart
        }
    }
}

}  // namespace
}  // namespace ddmr::test
