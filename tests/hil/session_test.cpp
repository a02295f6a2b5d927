// Session: the one engine (hil/session.hpp): its loop, its timed actions and
// ends, and sessions as independent objects (threads, many in a row).
#include "hil/session.hpp"

#include <gtest/gtest.h>

#include <malloc.h>

#include <cstddef>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

#if defined(__SANITIZE_ADDRESS__)
// The sanitizer runtime's count of bytes in use (declared in LLVM's
// <sanitizer/allocator_interface.h>, which GCC does not ship; libasan has it).
extern "C" std::size_t __sanitizer_get_current_allocated_bytes();
#endif

namespace ddmr::hil {
namespace {

/// What a run of the reference firmware produced, for comparisons.
struct Recording : SessionObserver {
    std::string text;
    std::string truth;  ///< x, y, theta of every ground-truth sample, bit-exact
    void on_host_byte(char c, Cycles /*cycle*/) override { text.push_back(c); }
    void on_truth(const TruthSample& s) override {
        for (double v : {s.x_m, s.y_m, s.theta_rad}) truth.append(reinterpret_cast<const char*>(&v), sizeof v);
    }
};

SessionOptions options_for(double seconds) {
    SessionOptions o;
    o.time_limit = s_to_cycles(seconds, test::kUnoClockHz);
    return o;
}

/// Boots the reference firmware (its setup() waits 5 s), sends `case_byte`
/// and runs `seconds` more of AVR time.
Recording run_reference(char case_byte, double seconds) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session session(elf, RigConfig{}, options_for(6.0 + seconds));
    Recording rec;
    session.attach(rec);
    EXPECT_EQ(session.run_to_first_return_from(elf.require("delay")), SessionStop::kCondition);
    session.send(std::string(1, case_byte));
    EXPECT_EQ(session.run(session.cycle() + s_to_cycles(seconds, test::kUnoClockHz)), SessionStop::kReachedCycle);
    return rec;
}

TEST(Session, TimedActionsRunInCycleOrderWithinOneInstructionOfTheirCycle) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session session(elf, RigConfig{}, options_for(1.0));
    std::vector<std::pair<char, Cycles>> ran;
    session.at(300'000, [&] { ran.push_back({'A', session.cycle()}); });
    session.at(100'000, [&] { ran.push_back({'B', session.cycle()}); });
    session.at(100'000, [&] { ran.push_back({'C', session.cycle()}); });  // same cycle: after B, as added
    EXPECT_EQ(session.run(400'000), SessionStop::kReachedCycle);
    ASSERT_EQ(ran.size(), 3U);
    EXPECT_EQ(ran[0].first, 'B');
    EXPECT_EQ(ran[1].first, 'C');
    EXPECT_EQ(ran[2].first, 'A');
    // The longest AVR instruction takes 5 cycles (CALL on a 22-bit PC); on the Uno 4.
    for (const auto& [name, cycle] : ran) {
        const Cycles due = name == 'A' ? 300'000 : 100'000;
        EXPECT_GE(cycle, due) << name;
        EXPECT_LE(cycle, due + 4) << name;
    }
    EXPECT_GE(session.cycle(), 400'000U);
}

TEST(Session, EndAfterEndsTheRunThatManyCyclesLaterAndLaterRunsEndAtOnce) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session session(elf, RigConfig{}, options_for(1.0));
    Cycles asked = 0;
    session.at(50'000, [&] {
        asked = session.cycle();
        session.end_after(20'000);
    });
    EXPECT_EQ(session.run(Session::kNoTarget), SessionStop::kEnded);
    EXPECT_GE(session.cycle(), asked + 20'000);
    EXPECT_LE(session.cycle(), asked + 20'000 + 4);
    const Cycles end = session.cycle();
    EXPECT_EQ(session.run(Session::kNoTarget), SessionStop::kEnded);
    EXPECT_EQ(session.cycle(), end);  // nothing ran
}

TEST(Session, TheTimeLimitEndsARunWithoutATarget) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session session(elf, RigConfig{}, options_for(0.01));  // 160,000 cycles
    EXPECT_EQ(session.run(Session::kNoTarget), SessionStop::kTimeLimit);
    EXPECT_GE(session.cycle(), 160'000U);
    EXPECT_LE(session.cycle(), 160'004U);
    EXPECT_TRUE(session.end_message(SessionStop::kTimeLimit).empty());  // the front end words it
}

TEST(Session, ABoundaryConditionStopsTheRunAtTheFirstBoundaryWhereItHolds) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Session session(elf, RigConfig{}, options_for(1.0));
    const Cycles step = session.rig().coupler().config().step_cycles;  // 1000 at 16 MHz
    ASSERT_EQ(step, 1000U);
    const auto met = [&] { return session.rig().robot().time_s() > 0.0050001; };
    EXPECT_EQ(session.run(Session::kNoTarget, RunCondition{met, /*poll_each_boundary=*/true}),
              SessionStop::kCondition);
    // The plant runs one step ahead: at boundary b (a multiple of 1000) its
    // time is (b + 1000) / 16 MHz, first past 5.0001 ms (80,001.6 cycles) at
    // b = 80,000; the run stops within one instruction of it.
    EXPECT_GE(session.cycle(), 80'000U);
    EXPECT_LE(session.cycle(), 80'000U + 4);
}

TEST(Session, InstrumentsLeftOffAreNotBuiltAndTheRunIsTheSame) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    SessionOptions off = options_for(0.3);
    off.instruments = {false, false, false};
    Session bare(elf, RigConfig{}, off);
    EXPECT_EQ(bare.isr_monitor(), nullptr);
    EXPECT_EQ(bare.stack_guard(), nullptr);
    EXPECT_EQ(bare.race_detector(), nullptr);
    Session full(elf, RigConfig{}, options_for(0.3));
    EXPECT_NE(full.isr_monitor(), nullptr);
    Recording a, b;
    bare.attach(a);
    full.attach(b);
    EXPECT_EQ(bare.run(Session::kNoTarget), SessionStop::kTimeLimit);
    EXPECT_EQ(full.run(Session::kNoTarget), SessionStop::kTimeLimit);
    EXPECT_FALSE(a.truth.empty());
    EXPECT_EQ(a.truth, b.truth);  // watching changes nothing
    EXPECT_EQ(a.text, b.text);
}

TEST(Session, SessionsInThreadsGiveTheBytesTheyGiveOneAfterAnother) {
    constexpr double kSeconds = 1.0;  // of the case, after the 5 s boot
    const Recording one = run_reference('1', kSeconds);
    const Recording two = run_reference('2', kSeconds);
    ASSERT_FALSE(one.text.empty());
    ASSERT_NE(one.truth, two.truth);  // the two cases drive differently: the comparison can tell
    std::vector<Recording> threaded(2);  // both cases at once, on two cores
    std::vector<std::thread> threads;
    for (std::size_t i = 0; i < threaded.size(); ++i) {
        threads.emplace_back([&threaded, i] { threaded[i] = run_reference(i % 2 == 0 ? '1' : '2', kSeconds); });
    }
    for (auto& t : threads) t.join();
    for (std::size_t i = 0; i < threaded.size(); ++i) {
        const Recording& want = i % 2 == 0 ? one : two;
        EXPECT_EQ(threaded[i].text, want.text) << i;
        EXPECT_EQ(threaded[i].truth, want.truth) << i;
    }
}

/// Heap bytes in use now (the sanitizer's allocator under ASan, glibc's otherwise).
std::size_t heap_in_use() {
#if defined(__SANITIZE_ADDRESS__)
    return __sanitizer_get_current_allocated_bytes();
#else
    return mallinfo2().uordblks;
#endif
}

TEST(Session, AThousandShortSessionsLeaveTheHeapAsTheyFoundIt) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    const auto one = [&elf] {
        Session session(elf, RigConfig{}, options_for(0.001));
        Recording rec;
        session.attach(rec);
        EXPECT_EQ(session.run(Session::kNoTarget), SessionStop::kTimeLimit);
    };
    for (int i = 0; i < 100; ++i) one();  // allocators' caches warm
    const std::size_t after_100 = heap_in_use();
    for (int i = 100; i < 1000; ++i) one();
    const std::size_t after_1000 = heap_in_use();
    // A leak of even 1 KiB a session would add 900 KiB; allow 64 KiB of noise.
    EXPECT_LT(after_1000, after_100 + 64 * 1024) << after_100 << " -> " << after_1000;
}

}  // namespace
}  // namespace ddmr::hil
