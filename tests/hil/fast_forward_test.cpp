// FastForward: skipped passes leave the machine exactly as executing them
// does. Two sessions of one firmware, one with fast-forward and one
// without, are stopped at the same cycles; their registers, I/O and SRAM
// (simavr's data space), SREG, PC and the bytes sent must be equal at each.
#include "hil/fast_forward.hpp"

#include <gtest/gtest.h>

#include <sim_avr.h>

#include <algorithm>
#include <cstring>
#include <string>
#include <vector>

#include "hil/function_profiler.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/session.hpp"
#include "support/loopback_tcp.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::hil {
namespace {

struct Bytes : SessionObserver {
    std::string text;
    void on_host_byte(char c, Cycles /*cycle*/) override { text.push_back(c); }
};

struct Twin {
    explicit Twin(const ElfImage& elf, bool fast_forward) : session(elf, RigConfig{}, options(fast_forward)) {
        session.attach(bytes);
    }
    static SessionOptions options(bool fast_forward) {
        SessionOptions o;
        o.time_limit = s_to_cycles(8.0, test::kUnoClockHz);
        o.fast_forward = fast_forward;
        return o;
    }
    Session session;
    Bytes bytes;
};

/// Every interrupt's raise, entry and exit cycle, and the summary, the same both ways.
void expect_same_isr_timing(Session& on, Session& off, const std::string& fixture) {
    const std::vector<IsrEvent>& a = on.isr_monitor()->events();
    const std::vector<IsrEvent>& b = off.isr_monitor()->events();
    ASSERT_EQ(a.size(), b.size()) << fixture;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const bool same = a[i].vector == b[i].vector && a[i].raise_cycle == b[i].raise_cycle &&
                          a[i].entry_cycle == b[i].entry_cycle && a[i].exit_cycle == b[i].exit_cycle;
        ASSERT_TRUE(same) << fixture << ": interrupt " << i << " (vector " << b[i].vector << ", entered at "
                          << b[i].entry_cycle << ") raised at " << a[i].raise_cycle.value_or(0)
                          << " with fast-forward, " << b[i].raise_cycle.value_or(0) << " without";
    }
    EXPECT_EQ(to_markdown(on.isr_monitor()->summary()), to_markdown(off.isr_monitor()->summary())) << fixture;
}

/// Runs `elf` both ways to each of `stops` and compares the whole machine.
FastForwardStats expect_identical_states(const std::string& fixture, const std::vector<Cycles>& stops) {
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / (fixture + ".elf"));
    Twin on(elf, true);
    Twin off(elf, false);
    for (Cycles stop : stops) {
        EXPECT_EQ(on.session.run(stop), SessionStop::kReachedCycle);
        EXPECT_EQ(off.session.run(stop), SessionStop::kReachedCycle);
        avr_t* a = on.session.core().raw();
        avr_t* b = off.session.core().raw();
        EXPECT_EQ(a->cycle, b->cycle) << fixture << " at " << stop;
        EXPECT_EQ(a->pc, b->pc) << fixture << " at " << stop;
        EXPECT_EQ(std::memcmp(a->sreg, b->sreg, sizeof a->sreg), 0) << fixture << " at " << stop;
        const std::size_t n = static_cast<std::size_t>(a->ramend) + 1;
        for (std::size_t i = 0; i < n; ++i) {
            if (a->data[i] != b->data[i]) {
                ADD_FAILURE() << fixture << ": data 0x" << std::hex << i << " differs at cycle " << std::dec << stop
                              << ": " << int(a->data[i]) << " with fast-forward, " << int(b->data[i]) << " without";
                break;
            }
        }
        EXPECT_EQ(on.bytes.text, off.bytes.text) << fixture << " at " << stop;
        for (int v = 1; v < static_cast<int>(on.session.core().mcu().vector_count()); ++v) {
            EXPECT_EQ(on.session.isr_monitor()->pending_since(v), off.session.isr_monitor()->pending_since(v))
                << fixture << ": vector " << v << "'s raise at " << stop;
        }
    }
    expect_same_isr_timing(on.session, off.session, fixture);
    EXPECT_EQ(off.session.core().fast_forward(), nullptr);
    return on.session.core().fast_forward()->stats();
}

/// Shorter jumps on average than this mean edges the loop cannot see bounded them (JumpsPastEncoderEdges...).
constexpr uint64_t kUnreadEdgeJumpCycles = 8000;

/// Cycles skipped per jump over the whole run (0 if nothing was skipped).
uint64_t mean_jump_cycles(const FastForwardStats& s) {
    uint64_t cycles = 0;
    uint64_t skips = 0;
    for (const SkippedLoop& l : s.loops) {
        cycles += l.cycles_skipped;
        skips += l.skips;
    }
    return skips == 0 ? 0 : cycles / skips;
}

/// What the fixture sent by cycle `end`, run with fast-forward.
std::string sent_by(const std::string& fixture, Cycles end) {
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / (fixture + ".elf"));
    Twin on(elf, true);
    EXPECT_EQ(on.session.run(end), SessionStop::kReachedCycle) << fixture;
    return on.bytes.text;
}

std::vector<Cycles> every(Cycles step, Cycles end) {
    std::vector<Cycles> out;
    for (Cycles c = step; c <= end; c += step) out.push_back(c);
    return out;
}

TEST(FastForward, SkipsAWaitButNotACounterInSram) {
    // ff_fixture.c, FF_SRAM_COUNTER: `while (us() - start < 5000) ++passes;`
    // then wait_us(3000): the first writes SRAM each pass, the second nothing.
    const FastForwardStats s = expect_identical_states("ff_sram_counter", every(97'003, 2'400'000));
    EXPECT_GT(s.cycles_skipped, 0U);
    bool counter_refused = false;
    for (const RefusedLoop& r : s.refused) counter_refused |= r.reason.find("from pass to pass") != std::string::npos;
    EXPECT_TRUE(counter_refused);
}

TEST(FastForward, WaitsForAnIsrFlagExactly) {
    // FF_ISR_FLAG: `while (!flag) {}`, flag set by Timer1's compare ISR every 10 ms.
    const FastForwardStats s = expect_identical_states("ff_isr_flag", every(151'007, 3'200'000));
    EXPECT_GT(s.cycles_skipped, 0U);
}

TEST(FastForward, PollsAPinThePlantDrivesExactly) {
    // FF_PIN_POLL: `while ((PIND & _BV(PD2)) == level) {}`, the encoder's edges from the plant.
    expect_identical_states("ff_pin_poll", every(123'457, 3'200'000));
}

TEST(FastForward, TheReferenceFirmwareMatchesItsCaseOneRun) {
    // The thesis firmware's boot (delay(5000)) and its first second of case 1.
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Twin on(elf, true);
    Twin off(elf, false);
    for (Twin* r : {&on, &off}) {
        ASSERT_EQ(r->session.run_to_first_return_from(elf.require("delay")), SessionStop::kCondition);
    }
    EXPECT_EQ(on.session.cycle(), off.session.cycle());  // the boot's end, found by sampling, is the same
    for (Twin* r : {&on, &off}) {
        r->session.send("1");
        EXPECT_EQ(r->session.run(r->session.cycle() + s_to_cycles(1.0, test::kUnoClockHz)), SessionStop::kReachedCycle);
    }
    EXPECT_EQ(on.bytes.text, off.bytes.text);
    EXPECT_EQ(std::memcmp(on.session.core().raw()->data, off.session.core().raw()->data,
                          static_cast<std::size_t>(on.session.core().raw()->ramend) + 1),
              0);
    const FastForwardStats s = on.session.core().fast_forward()->stats();
    // delay() dominates the boot: most of its 5 s are skipped, the coupling
    // steps run inside the skips (they would cut them to 1000 cycles), and
    // the EEPROM busy-wait of case 1's log is skipped too.
    EXPECT_GT(static_cast<double>(s.cycles_skipped) / static_cast<double>(on.session.cycle()), 0.8);
    EXPECT_TRUE(std::any_of(s.loops.begin(), s.loops.end(), [&](const SkippedLoop& l) {
        const auto fn = elf.function_at(l.anchor);
        return l.skips > 0 && fn && fn->name == "eeprom_write_byte";
    }));
}

// A condition polled at each coupling boundary, met inside a skip (the
// boot's delay(5000): coupling steps run inside the skips), stops the run at
// the boundary's own cycle, as without fast-forward: the skip is taken back
// and the stop deferred to there.
TEST(FastForward, AStopAStepInsideASkipAsksForComesAtItsOwnCycle) {
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    Twin on(elf, true);
    Twin off(elf, false);
    for (const Cycles t : {Cycles{1'234'567}, Cycles{2'345'678}, Cycles{3'456'789}}) {
        for (Twin* r : {&on, &off}) {
            const Session& s = r->session;
            const RunCondition until{[&s, t] { return s.cycle() >= t; }, true};
            EXPECT_EQ(r->session.run(Session::kNoTarget, until), SessionStop::kCondition);
        }
        EXPECT_EQ(on.session.cycle(), off.session.cycle()) << t;
        EXPECT_GE(on.session.cycle(), t);
        EXPECT_LT(on.session.cycle(), t + 1000 + 5);  // the first boundary after t, and its instruction's end
        EXPECT_EQ(std::memcmp(on.session.core().raw()->data, off.session.core().raw()->data,
                              static_cast<std::size_t>(on.session.core().raw()->ramend) + 1),
                  0)
            << t;
    }
    EXPECT_GT(on.session.core().fast_forward()->stats().taken_back, 0U);
}

TEST(FastForward, AFlagRaisedInsideASkipIsStampedAtItsOwnCycle) {
    // FF_LATE_ENABLE: TOV2 (phase-correct Timer2, its interrupt off) is
    // raised inside skipped waits and replayed after each jump: the cycle
    // IsrMonitor stamps the raise with (pending_since) must be the one
    // executing gives, and the interrupt enabled later is entered (simavr
    // 1.6 at the next raise) with the same latency.
    const FastForwardStats s = expect_identical_states("ff_late_enable", every(61'001, 1'000'000));
    EXPECT_GT(s.cycles_skipped, 0U);
}

TEST(FastForward, SkipsAKitRobotsLoopThatWritesThePinsTheValuesTheyHold) {
    // FF_PORT_WRITES: a loop() that sets the motor pins (PORTB), a pin's
    // direction (DDRB), TCCR0A and OCR0B again each pass, through a function
    // the pass runs through four times, and reads encoder 1's pin: skipped,
    // learned from a PC the pass runs through once. Then writes that are not
    // inert in simavr 1.6 (a PCMSK0 bit on an output, a PORTD write beside
    // Timer0's PWM on OC0B, a pin set low and high each pass), exact as well.
    const FastForwardStats s = expect_identical_states("ff_port_writes", every(99'989, 6'400'000));
    uint64_t writing_loop_skipped = 0;
    for (const SkippedLoop& l : s.loops) {
        const auto passes_at = [&l](uint32_t pc) { return std::count(l.path.begin(), l.path.end(), pc); };
        const bool repeats_a_pc = std::any_of(l.path.begin(), l.path.end(), [&](uint32_t pc) { return passes_at(pc) > 1; });
        if (repeats_a_pc && passes_at(l.anchor) == 1) writing_loop_skipped += l.cycles_skipped;
    }
    EXPECT_GT(writing_loop_skipped, 1'000'000U);
    bool toggle_refused = false;
    for (const RefusedLoop& r : s.refused) toggle_refused |= r.reason.find("writes PORTB a new value") != std::string::npos;
    EXPECT_TRUE(toggle_refused);
}

TEST(FastForward, JumpsPastEncoderEdgesALoopCannotSee) {
    // FF_UNREAD_EDGES: the encoders' edges while loops wait without reading
    // PIND, with INT0/INT1 and PCINT2 off (the edges only set flags, or, in
    // low-level sense, set INTFn only with the I flag set), then with PCINT2
    // on. The same state both ways at every stop; the flags and the ISR's
    // count are printed.
    const FastForwardStats s = expect_identical_states("ff_unread_edges", every(49'999, 3'850'000));
    // Raised after the jumps (PinDriver's edges are replayable while no
    // interrupt is on): the waits' jumps end at Timer0's overflows (16,384
    // cycles), not at the edges (about 11,500 cycles a jump; under 5,000
    // when the edges bound them).
    EXPECT_GT(mean_jump_cycles(s), kUnreadEdgeJumpCycles);
}

TEST(FastForward, JumpsPastEdgesOnPinBitsALoopMasksOff) {
    // FF_MASKED_PIN: loops that read the whole of PIND and use bit 7 only
    // (digitalRead()'s load and mask, SBIS) while the encoders change bits 2
    // and 3, up to about 1.65 M cycles; then the same digitalRead() counts
    // encoder 1's edges, which bound its jumps. The same state both ways at
    // every stop.
    const FastForwardStats s = expect_identical_states("ff_masked_pin", every(49'999, 1'600'000));
    // The waits' jumps end at Timer0's overflows (about 11,500 cycles a
    // jump), not at the edges on bits 2 and 3 (under 5,000 a jump).
    EXPECT_GT(mean_jump_cycles(s), kUnreadEdgeJumpCycles);
    (void)expect_identical_states("ff_masked_pin", every(49'999, 3'700'000));
    const std::string sent = sent_by("ff_masked_pin", 3'700'000);
    EXPECT_NE(sent.find("edges 20"), std::string::npos) << sent;
}

TEST(FastForward, JumpsPastTheEdgesOfPwmOutputsALoopDoesNotRead) {
    // FF_OC_PWM: Timer0's and Timer1's compare units drive OC0A/OC0B and
    // OC1A/OC1B (four changes per 800 cycles on D9/D10) while a wait reads
    // none of the pins, up to about 0.85 M cycles; then a wait reads PINB
    // (simavr 1.6 stores PORTB's bits into its output bits on each read)
    // and PCINT1 on OC1A requests interrupts, both of which bound the jumps;
    // then OC1A toggles (simavr writes PORTB: never replayed). The same
    // state both ways at every stop.
    const FastForwardStats s = expect_identical_states("ff_oc_pwm", every(49'999, 850'000));
    // The wait's jumps end at Timer0's overflows (about 11,500 cycles a
    // jump), not at the OC changes (under 800 a jump).
    EXPECT_GT(mean_jump_cycles(s), kUnreadEdgeJumpCycles);
    (void)expect_identical_states("ff_oc_pwm", every(49'999, 2'600'000));
    const std::string sent = sent_by("ff_oc_pwm", 2'600'000);
    EXPECT_NE(sent.find("toggle"), std::string::npos) << sent;
    EXPECT_EQ(sent.find("pcint 0 "), std::string::npos) << sent;  // the ISR counted changes
}

TEST(FastForward, LeavesEdgesOnATimersClockPinWhereTheyFall) {
    // FF_T1_CLOCK: Timer1 counts the falling edges of OC0B's PWM on its T1
    // pin while a loop polls TCNT1: an edge replayed after a jump would
    // count late (without the rule the states part at 700,000 cycles). The
    // same state both ways at every stop, and the poll ends.
    const FastForwardStats s = expect_identical_states("ff_t1_clock", every(49'999, 1'000'000));
    EXPECT_GT(s.cycles_skipped, 0U);  // the poll itself is skipped up to each edge
    const std::string sent = sent_by("ff_t1_clock", 1'000'000);
    EXPECT_NE(sent.find("t1 40 "), std::string::npos) << sent;
}

TEST(FastForward, PollsTheCountOfAPhaseCorrectTimerExactly) {
    // FF_TCNT2_POLL: `while (TCNT2 < high) {}` and `while (TCNT2 > low) {}`
    // on Timer2 counting 0..TOP..0 (PhaseCorrectTimer), with TOP 0xFF, then
    // OCR2A as TOP, then a new OCR2A: each exit at the same cycle, with the
    // same count, both ways.
    const FastForwardStats s = expect_identical_states("ff_tcnt2_poll", every(97'007, 5'200'000));
    EXPECT_GT(s.cycles_skipped, 0U);
    const std::string sent = sent_by("ff_tcnt2_poll", 5'200'000);
    EXPECT_NE(sent.find("done"), std::string::npos) << sent;  // all nine polls ended
}

TEST(FastForward, PredictsTheMillisecondsOfADelayAtEveryStackDepth) {
    // FF_DELAY_MS: delay()'s algorithm, its path changing every 16,000
    // cycles: 100 ms from run(), then 100 ms three calls deeper (another SP).
    // Exact both ways; each half is mostly skipped (the second less: it
    // includes most of two lines sent), and the changes are predicted: with
    // a bisection at each, checked passes left the path 537 times.
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_delay_ms.elf");
    (void)expect_identical_states("ff_delay_ms", every(99'991, 3'600'000));
    Twin on(elf, true);
    const auto skipped = [&on] { return on.session.core().fast_forward()->stats().cycles_skipped; };
    const auto run_to_line = [&on](const std::string& line) {
        const RunCondition until{[&on, &line] { return on.bytes.text.find(line) != std::string::npos; }, true};
        EXPECT_EQ(on.session.run(Session::kNoTarget, until), SessionStop::kCondition) << line;
        return on.session.cycle();
    };
    const Cycles first_end = run_to_line("delay 100");
    const Cycles first_skipped = skipped();
    const Cycles second_start = on.session.cycle();
    const Cycles second_end = run_to_line("delay 200");
    EXPECT_GT(static_cast<double>(first_skipped) / static_cast<double>(first_end), 0.85);
    EXPECT_GT(static_cast<double>(skipped() - first_skipped) / static_cast<double>(second_end - second_start), 0.75);
    EXPECT_LT(on.session.core().fast_forward()->stats().mismatches, 150U);  // 200 changes of path
}

/// An instruction hook that reads only the PC, SP and cycle: a digest of
/// every (PC, SP, cycle) it was shown, in order.
struct StepDigest {
    explicit StepDigest(AvrCore& core) : core_(core) {
        core_.add_instruction_hook(this, [this] { on_step(); }, AvrCore::HookReads::kPcSpCycle);
    }
    ~StepDigest() { core_.remove_instruction_hook(this); }
    StepDigest(const StepDigest&) = delete;
    StepDigest& operator=(const StepDigest&) = delete;
    void on_step() {
        for (const uint64_t v : {uint64_t{core_.pc()}, uint64_t{core_.stack_pointer()}, core_.cycle()}) {
            digest = (digest ^ v) * 0x100000001b3ULL;  // FNV-1a over the three values
        }
        ++steps;
    }
    AvrCore& core_;
    uint64_t digest = 0xcbf29ce484222325ULL;
    uint64_t steps = 0;
};

TEST(FastForward, InstructionHooksSeeEverySkippedInstructionAsSteppingShowsIt) {
    // FF_DELAY_MS with a function profiler and a (PC, SP, cycle) digest:
    // fast-forward stays on, and shows the hooks each instruction of the
    // passes it skips, with the PC, SP and cycle it had, in order. Both
    // must come out as without fast-forward.
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_delay_ms.elf");
    Twin on(elf, true);
    Twin off(elf, false);
    StepDigest on_digest(on.session.core());
    StepDigest off_digest(off.session.core());
    FunctionProfiler on_profile(on.session.core());
    FunctionProfiler off_profile(off.session.core());
    for (Twin* r : {&on, &off}) EXPECT_EQ(r->session.run(3'600'000), SessionStop::kReachedCycle);
    EXPECT_EQ(on_digest.steps, off_digest.steps);
    EXPECT_EQ(on_digest.digest, off_digest.digest);
    const ProfileScope a = on_profile.whole_run();
    const ProfileScope b = off_profile.whole_run();
    EXPECT_EQ(a.cycles, b.cycles);
    ASSERT_EQ(a.functions.size(), b.functions.size());
    for (std::size_t f = 0; f < a.functions.size(); ++f) {
        EXPECT_EQ(a.functions[f].calls, b.functions[f].calls) << on_profile.map().function(static_cast<FunctionId>(f)).name;
        EXPECT_EQ(a.functions[f].self_cycles, b.functions[f].self_cycles) << f;
        EXPECT_EQ(a.functions[f].inclusive_cycles, b.functions[f].inclusive_cycles) << f;
    }
    EXPECT_EQ(a.word_cycles, b.word_cycles);
    EXPECT_EQ(on.bytes.text, off.bytes.text);
    const FastForwardStats s = on.session.core().fast_forward()->stats();
    // The coupling steps run inside the skips, the hooks are shown the passes after.
    EXPECT_GT(static_cast<double>(s.cycles_skipped), 0.8 * 3'600'000);
}

TEST(FastForward, ALoopProfilerIsShownEverySkippedPassThatEntersItsMark) {
    // FF_PORT_WRITES with the loop profiler's mark on set_pin(), which each
    // pass of the skipped loop calls four times: every pass enters and
    // leaves the mark, so every skipped pass must be shown to it (the
    // profiler counts its state's changes: it is shown only the first pass
    // of a skip where that pass changed nothing), and each return of the
    // mark is an iteration at the cycle stepping gives.
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_port_writes.elf");
    Twin on(elf, true);
    Twin off(elf, false);
    LoopProfiler on_loop(on.session.core(), elf.require("set_pin"));
    LoopProfiler off_loop(off.session.core(), elf.require("set_pin"));
    on_loop.arm();
    off_loop.arm();
    for (Twin* r : {&on, &off}) EXPECT_EQ(r->session.run(2'000'000), SessionStop::kReachedCycle);
    const std::vector<LoopIteration>& a = on_loop.iterations();
    const std::vector<LoopIteration>& b = off_loop.iterations();
    ASSERT_EQ(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        ASSERT_TRUE(a[i].start == b[i].start && a[i].mark_entry == b[i].mark_entry && a[i].end == b[i].end)
            << "iteration " << i << " ends at " << a[i].end << " with fast-forward, " << b[i].end << " without";
    }
    EXPECT_GT(a.size(), 1000U);
    EXPECT_GT(on.session.core().fast_forward()->stats().cycles_skipped, 500'000U);
}

TEST(FastForward, AnInstructionHookThatReadsMoreTurnsSkippingOff) {
    // A hook that may read anything (avr-gdb's) sees the machine after every
    // instruction: nothing is skipped while it is installed.
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_delay_ms.elf");
    Twin on(elf, true);
    uint64_t steps = 0;
    on.session.core().add_instruction_hook(&steps, [&steps] { ++steps; });
    EXPECT_EQ(on.session.run(1'000'000), SessionStop::kReachedCycle);
    EXPECT_EQ(on.session.core().fast_forward()->stats().cycles_skipped, 0U);
    on.session.core().remove_instruction_hook(&steps);
    EXPECT_EQ(on.session.run(2'000'000), SessionStop::kReachedCycle);
    EXPECT_GT(on.session.core().fast_forward()->stats().cycles_skipped, 500'000U);
    EXPECT_GT(steps, 300'000U);
}

TEST(FastForward, AWatchdogResetWhileItStepsIsTheCoresReset) {
    // FF_WATCHDOG: the watchdog resets the chip about every 16 ms inside a
    // wait loop fast-forward learns, walks and skips. Each reset must come
    // at the same cycle both ways and go through AvrCore::reset (the run's
    // parts re-armed, the run's own target kept).
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_watchdog.elf");
    Twin on(elf, true);
    Twin off(elf, false);
    const Cycles end = 8'000'000;
    std::vector<Cycles> resets[2];
    for (int n = 0; n < 2; ++n) {
        AvrCore& core = (n == 0 ? on : off).session.core();
        while (core.cycle() < end) {
            const RunStop stop = core.run_until(end);
            if (stop == RunStop::kWatchdogReset) {
                resets[n].push_back(core.cycle());
            } else {
                ASSERT_EQ(stop, RunStop::kReachedCycle);
            }
        }
    }
    EXPECT_EQ(resets[0], resets[1]);
    EXPECT_GT(resets[1].size(), 20U);
    EXPECT_EQ(on.session.core().watchdog_resets(), resets[0].size());
    EXPECT_EQ(on.bytes.text, off.bytes.text);
    EXPECT_EQ(std::memcmp(on.session.core().raw()->data, off.session.core().raw()->data,
                          static_cast<std::size_t>(on.session.core().raw()->ramend) + 1),
              0);
    EXPECT_GT(on.session.core().fast_forward()->stats().cycles_skipped, 0U);
}

TEST(FastForward, GdbTurnsItOff) {
    SessionOptions o;
    o.time_limit = 1000;
    o.gdb = GdbServerConfig{test::free_loopback_port(), 1.0};
    const ElfImage elf = ElfImage::read(test::test_firmware_dir() / "ff_isr_flag.elf");
    Session session(elf, RigConfig{}, o);
    EXPECT_EQ(session.core().fast_forward(), nullptr);
}

}  // namespace
}  // namespace ddmr::hil
