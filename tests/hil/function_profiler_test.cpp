// FunctionProfiler: exact self/inclusive cycles and calls on a hand-counted
// fixture, and the accounting identities on the reference firmware (case 1).
#include "hil/function_profiler.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "hil/isr_monitor.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/robot_rig.hpp"
#include "support/square_wave_input.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using hil::Cycles;
using hil::FunctionCounts;
using hil::FunctionProfiler;

const FunctionCounts& counts(const FunctionProfiler& p, const hil::ProfileScope& scope, const char* name) {
    const auto id = p.map().find(name);
    if (!id) throw std::runtime_error(std::string("no function ") + name);
    return scope.functions[*id];
}

Cycles self_sum(const hil::ProfileScope& scope) {
    return std::accumulate(scope.functions.begin(), scope.functions.end(), Cycles{0},
                           [](Cycles a, const FunctionCounts& f) { return a + f.self_cycles; });
}

/// A caller -> callee edge of `scope`, its call sites summed; caller nullptr
/// is <spontaneous> (no caller).
struct EdgeSum {
    uint64_t calls = 0;
    Cycles inclusive_cycles = 0;
    std::size_t sites = 0;  ///< call sites with calls or cycles in the scope
};

EdgeSum edge(const FunctionProfiler& p, const hil::ProfileScope& scope, const char* caller, const char* callee) {
    const hil::FunctionId from = caller == nullptr ? hil::CallEdge::kNoCaller : *p.map().find(caller);
    const hil::FunctionId to = *p.map().find(callee);
    EdgeSum sum;
    for (std::size_t i = 0; i < scope.edges.size(); ++i) {
        const hil::CallEdge& e = p.edges()[i];
        const hil::EdgeCounts& c = scope.edges[i];
        if (e.caller != from || e.callee != to || (c.calls == 0 && c.inclusive_cycles == 0)) continue;
        sum.calls += c.calls;
        sum.inclusive_cycles += c.inclusive_cycles;
        ++sum.sites;
    }
    return sum;
}

std::size_t active_edges(const hil::ProfileScope& scope) {
    return static_cast<std::size_t>(std::count_if(scope.edges.begin(), scope.edges.end(), [](const hil::EdgeCounts& c) {
        return c.calls != 0 || c.inclusive_cycles != 0;
    }));
}

/// The call graph's and the per-word counts' identities, for any scope: the
/// edges into a function sum to its calls and inclusive cycles; the edges out
/// of it to at most its inclusive cycles (they are its callees' share of it);
/// a call site is in its caller; a function's words sum to its self cycles.
void expect_consistent(const FunctionProfiler& p, const hil::ProfileScope& scope) {
    const std::size_t n = p.map().size();
    std::vector<uint64_t> calls_in(n, 0);
    std::vector<Cycles> inclusive_in(n, 0);
    std::vector<Cycles> inclusive_out(n, 0);
    ASSERT_LE(scope.edges.size(), p.edges().size());
    for (std::size_t i = 0; i < scope.edges.size(); ++i) {
        const hil::CallEdge& e = p.edges()[i];
        calls_in[e.callee] += scope.edges[i].calls;
        inclusive_in[e.callee] += scope.edges[i].inclusive_cycles;
        if (e.caller == hil::CallEdge::kNoCaller) {
            EXPECT_EQ(e.site, hil::CallEdge::kNoSite);
            continue;
        }
        inclusive_out[e.caller] += scope.edges[i].inclusive_cycles;
        EXPECT_EQ(p.map().at(e.site), e.caller) << p.map().function(e.caller).name << " site 0x" << std::hex << e.site;
    }
    for (std::size_t id = 0; id < n; ++id) {
        const auto& info = p.map().function(static_cast<hil::FunctionId>(id));
        const FunctionCounts& f = scope.functions[id];
        EXPECT_EQ(calls_in[id], f.calls) << info.name;
        EXPECT_EQ(inclusive_in[id], f.inclusive_cycles) << info.name;
        EXPECT_LE(inclusive_out[id], f.inclusive_cycles) << info.name;
        if (static_cast<hil::FunctionId>(id) == p.map().outside()) continue;
        Cycles words = 0;
        for (uint32_t a = info.address; a < info.end; a += 2) words += scope.word_cycles[a / 2];
        EXPECT_EQ(words, f.self_cycles) << info.name;
    }
    EXPECT_EQ(std::accumulate(scope.word_cycles.begin(), scope.word_cycles.end(), Cycles{0}), scope.cycles);
}

// tests/firmware/profile_fixture.c (avr-objdump -d; cycles from the
// ATmega328P instruction set summary, 16-bit PC: NOP 1, RJMP 2, JMP 3,
// CALL 4, RET 4, RETI 4):
//   0x0000 __vectors:  jmp __init (reset, 3); 0x0004 jmp __vector_1 (3)
//   0x0068 __init:     eor, out, ldi, ldi, out, out (6 x 1), call main (4) = 10
//   0x0080 leaf:       nop x4, ret                           = 8
//   0x008a middle:     nop, call leaf, nop, ret              = 10 self
//   0x0094 tailer:     nop, jmp leaf                         = 4 self
//   0x009a mark:       nop, nop, ret                         = 6
//   0x00a0 __vector_1: nop, call leaf, nop, reti             = 10 self
//   0x00b4 main loop:  call middle, call tailer, call mark, rjmp .-14 = 14 self
// One iteration of the loop, from mark's return to the next (N of them):
//   main self 14, calls 0, inclusive 50 (everything below it)
//   middle self 10, calls 1, inclusive 10 + 8 = 18
//   tailer self 4, calls 1, inclusive 4 + 8 = 12 (leaf's tail frame is above it)
//   leaf self 16, calls 2 (one CALL, one tail JMP), inclusive 16
//   mark self 6, calls 1, inclusive 6                          period 50
// One INT0 interrupt (E of them), wherever it lands:
//   __vectors self 3 (its JMP), __vector_1 self 10, calls 1, inclusive 18,
//   leaf self +8, calls +1; 21 cycles of interrupt time, none of them charged
//   to the interrupted function's inclusive.
//
// The same program for the ATmega2560 (22-bit PC, 3-byte return addresses:
// CALL 5, RET 5, RETI 5; datasheet 2549Q, instruction set summary; INT0 on
// PD0): __init adds ldi r16 / out EIND (8 x 1 + call 5 = 13); leaf 9,
// middle 12 self, tailer 4, mark 7, __vector_1 12 self, main 3 x 5 + 2 = 17
// self; a period of 17 + 12 + 9 + 4 + 9 + 7 = 58 and an interrupt of
// 3 + 12 + 9 = 24 cycles.
struct ProfileFixture {
    const char* name;
    const char* elf;
    hil::BoardModel board;
    int int0_bit;  ///< INT0 is PD2 on the ATmega328P, PD0 on the ATmega2560
    Cycles init, leaf, middle, tailer, mark, vector, main;  ///< self cycles, as above
};

class FunctionProfilerFixture : public ::testing::TestWithParam<ProfileFixture> {};

TEST_P(FunctionProfilerFixture, HasHandCountedCyclesAndCalls) {
    const ProfileFixture& c = GetParam();
    const auto elf = hil::ElfImage::read(test_firmware_dir() / c.elf);
    hil::AvrCoreConfig config;
    config.board = c.board;
    hil::AvrCore core(elf, config);
    FunctionProfiler prof(core);  // before the first instruction: the whole stack
    prof.set_wait_function(*prof.map().find("mark"));  // the compute scope: the loop outside mark
    hil::LoopProfiler loop(core, elf.require("mark"));
    loop.set_iteration_listener([&](bool completed) { prof.on_loop_boundary(completed); });
    loop.arm();
    // INT0 edges every 997 cycles: they land in every function of the loop.
    SquareWaveInput wave(core, 'D', c.int0_bit, 997);
    core.run_until(100'000);

    const Cycles period = c.main + c.middle + c.leaf + c.tailer + c.leaf + c.mark;  // 50 on the Uno
    const Cycles isr = 3 + c.vector + c.leaf;                                      // 21 on the Uno
    const auto& cl = prof.control_loop();
    const uint64_t n = cl.iterations;
    const uint64_t e = counts(prof, cl, "__vector_1").calls;
    ASSERT_EQ(n, loop.iterations().size());
    ASSERT_GT(n, 1500u);  // 100,000 cycles / (period + ISRs) per iteration
    ASSERT_GT(e, 90u);    // 100 edges, all but the first and last few inside iterations
    Cycles periods = 0;
    for (const auto& it : loop.iterations()) periods += it.period();
    EXPECT_EQ(cl.cycles, periods);
    EXPECT_EQ(cl.cycles, period * n + isr * e);
    EXPECT_EQ(cl.interrupt_cycles, isr * e);
    EXPECT_EQ(self_sum(cl), cl.cycles);

    const auto check = [&](const char* name, uint64_t calls, Cycles self, Cycles inclusive) {
        const FunctionCounts& f = counts(prof, cl, name);
        EXPECT_EQ(f.calls, calls) << name;
        EXPECT_EQ(f.self_cycles, self) << name;
        EXPECT_EQ(f.inclusive_cycles, inclusive) << name;
    };
    check("main", 0, c.main * n, period * n);  // interrupts are not charged to main
    check("middle", n, c.middle * n, (c.middle + c.leaf) * n);
    check("tailer", n, c.tailer * n, (c.tailer + c.leaf) * n);
    check("leaf", 2 * n + e, (2 * n + e) * c.leaf, (2 * n + e) * c.leaf);
    check("mark", n, c.mark * n, c.mark * n);
    check("__vector_1", e, c.vector * e, (c.vector + c.leaf) * e);
    // The root frame: all non-interrupt cycles plus the vector JMPs.
    check("__vectors", 0, 3 * e, period * n + 3 * e);

    // Compute: the same iterations without mark's own cycles (nop, nop, ret;
    // the CALL to it is main's) and without the k interrupts taken while
    // mark's frame was open. Every function's compute self cycles but mark's
    // and the ISR's are its loop ones. The total is the loop profiler's
    // compute() but for an interrupt simavr takes in the same step as the
    // CALL to mark (or the RET from it): this scope charges it to the wait
    // (the return address is pushed, the PC in mark), compute() to the
    // compute (mark's first instruction has not run): whole interrupts apart.
    const auto& cp = prof.compute();
    EXPECT_EQ(cp.iterations, n);
    Cycles computes = 0;
    for (const auto& it : loop.iterations()) computes += it.compute();
    const Cycles apart = computes > cp.cycles ? computes - cp.cycles : cp.cycles - computes;
    EXPECT_EQ(apart % isr, 0u) << computes << " vs " << cp.cycles;
    EXPECT_LE(apart, 2 * isr);
    const Cycles in_mark = cl.cycles - cp.cycles - c.mark * n;  // the interrupts' cycles inside mark
    EXPECT_EQ(in_mark % isr, 0u);
    const uint64_t k = in_mark / isr;
    EXPECT_GT(k, 0u);  // 997 against 50: some edges land in mark's 6 cycles
    EXPECT_LT(k, e);
    EXPECT_EQ(cp.cycles, (period - c.mark) * n + isr * (e - k));
    EXPECT_EQ(cp.interrupt_cycles, isr * (e - k));
    EXPECT_EQ(self_sum(cp), cp.cycles);
    EXPECT_EQ(counts(prof, cp, "mark").self_cycles, 0u);
    EXPECT_EQ(counts(prof, cp, "main").self_cycles, c.main * n);
    EXPECT_EQ(counts(prof, cp, "middle").self_cycles, c.middle * n);
    EXPECT_EQ(counts(prof, cp, "tailer").self_cycles, c.tailer * n);
    EXPECT_EQ(counts(prof, cp, "leaf").self_cycles, (2 * n + e - k) * c.leaf);
    EXPECT_EQ(counts(prof, cp, "__vector_1").self_cycles, c.vector * (e - k));

    // The call graph of the control loop, edge by edge: a CALL or JMP site
    // each, or <spontaneous> (nullptr). The frames open since before the loop
    // (__vectors, __init, main) make no call in it but carry its cycles.
    const auto check_edge = [&](const char* caller, const char* callee, uint64_t calls, Cycles inclusive) {
        const EdgeSum sum = edge(prof, cl, caller, callee);
        const std::string name = std::string(caller == nullptr ? "<spontaneous>" : caller) + " -> " + callee;
        EXPECT_EQ(sum.calls, calls) << name;
        EXPECT_EQ(sum.inclusive_cycles, inclusive) << name;
        EXPECT_EQ(sum.sites, 1u) << name;
    };
    check_edge("main", "middle", n, (c.middle + c.leaf) * n);
    check_edge("middle", "leaf", n, c.leaf * n);
    check_edge("main", "tailer", n, (c.tailer + c.leaf) * n);
    check_edge("tailer", "leaf", n, c.leaf * n);  // the JMP: a tail frame above tailer's
    check_edge("main", "mark", n, c.mark * n);
    check_edge(nullptr, "__vector_1", e, (c.vector + c.leaf) * e);
    check_edge("__vector_1", "leaf", e, c.leaf * e);
    check_edge(nullptr, "__vectors", 0, period * n + 3 * e);  // the root frame, and each interrupt's vector JMP
    check_edge("__vectors", "__init", 0, period * n);
    check_edge("__init", "main", 0, period * n);
    EXPECT_EQ(active_edges(cl), 10u);
    expect_consistent(prof, cl);
    // Per instruction: leaf's first NOP ran once per call, its RET (the rest
    // of its cycles after the four NOPs) too.
    const auto& leaf_info = prof.map().function(*prof.map().find("leaf"));
    const uint64_t leaf_calls = 2 * n + e;
    EXPECT_EQ(cl.word_cycles[leaf_info.address / 2], leaf_calls);
    EXPECT_EQ(cl.word_cycles[leaf_info.address / 2 + 4], (c.leaf - 4) * leaf_calls);

    // Whole run: start-up code exactly; every cycle in exactly one function.
    const auto& all = prof.whole_run();
    EXPECT_EQ(all.cycles, core.cycle());
    EXPECT_EQ(self_sum(all), all.cycles);
    const FunctionCounts& init = counts(prof, all, "__init");
    EXPECT_EQ(init.calls, 1u);  // the reset vector's JMP
    EXPECT_EQ(init.self_cycles, c.init);
    EXPECT_EQ(counts(prof, all, "main").calls, 1u);
    const uint64_t e_all = counts(prof, all, "__vector_1").calls;
    EXPECT_EQ(e_all, wave.edges());
    EXPECT_EQ(counts(prof, all, "__vectors").self_cycles, 3 + 3 * e_all);
    EXPECT_EQ(counts(prof, all, "__vectors").inclusive_cycles, all.cycles - all.interrupt_cycles + 3 * e_all);
    EXPECT_EQ(counts(prof, all, "__bad_interrupt").calls, 0u);
    expect_consistent(prof, all);
    EXPECT_EQ(edge(prof, all, "__init", "main").calls, 1u);
    EXPECT_EQ(edge(prof, all, nullptr, "__vector_1").calls, e_all);
    // The stack: __vectors, __init (tail), main, middle, leaf, __vector_1, leaf at most.
    EXPECT_LE(prof.max_depth_seen(), 7u);
    EXPECT_EQ(prof.stack_overflows(), 0u);
    EXPECT_EQ(prof.mid_function_branches(), 0u);
    const auto stack = prof.call_stack();
    ASSERT_GE(stack.size(), 3u);
    EXPECT_EQ(prof.map().function(stack[0]).name, "__vectors");
    EXPECT_EQ(prof.map().function(stack[1]).name, "__init");
    EXPECT_EQ(prof.map().function(stack[2]).name, "main");
}

INSTANTIATE_TEST_SUITE_P(
    Mcus, FunctionProfilerFixture,
    ::testing::Values(ProfileFixture{"atmega328p", "profile_fixture.elf", hil::BoardModel::uno, 2, 10, 8, 10, 4, 6, 10, 14},
                      ProfileFixture{"atmega2560", "profile_fixture_atmega2560.elf", hil::BoardModel::mega2560, 0, 13,
                                     9, 12, 4, 7, 12, 17}),
    [](const ::testing::TestParamInfo<ProfileFixture>& p) { return std::string(p.param.name); });

TEST(FunctionProfiler, BoundedStackOverflowsButKeepsSelfCyclesExact) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "profile_fixture.elf");
    hil::AvrCore core(elf);
    FunctionProfiler prof(core, 3);  // __vectors, __init, main: no room for callees
    SquareWaveInput wave(core, 'D', 2, 997);
    core.run_until(20'000);
    EXPECT_EQ(prof.max_depth_seen(), 3u);
    EXPECT_GT(prof.stack_overflows(), 100u);
    EXPECT_EQ(prof.call_stack().size(), 3u);
    EXPECT_EQ(self_sum(prof.whole_run()), core.cycle());
    const auto all = prof.whole_run();
    EXPECT_EQ(std::accumulate(all.word_cycles.begin(), all.word_cycles.end(), Cycles{0}), core.cycle());
    EXPECT_THROW(FunctionProfiler(core, 1), std::invalid_argument);
}

TEST(FunctionProfiler, ReferenceFirmwareCase1) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::RobotRig rig(elf, hil::RigConfig{});
    hil::AvrCore& core = rig.core();
    FunctionProfiler prof(core);
    hil::IsrMonitor isr(core, elf);
    hil::LoopProfiler loop(core, elf.require("delay"));
    loop.set_iteration_listener([&](bool completed) { prof.on_loop_boundary(completed); });
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)), hil::RunStop::kCondition);
    loop.arm();
    rig.uart().send("1");
    core.run_until(core.cycle() + hil::s_to_cycles(13.0, kUnoClockHz));

    const auto& all = prof.whole_run();
    const auto& cl = prof.control_loop();
    // Every cycle observed is some function's self cycle.
    EXPECT_EQ(all.cycles, core.cycle());
    EXPECT_EQ(self_sum(all), all.cycles);
    EXPECT_EQ(self_sum(cl), cl.cycles);
    // The float and math routines the control law runs on.
    for (const char* name : {"__mulsf3", "__addsf3", "sin", "cos", "__fp_powser"}) {
        EXPECT_GT(counts(prof, cl, name).calls, 1000u) << name;
        EXPECT_GT(counts(prof, cl, name).self_cycles, 0u) << name;
    }
    // One delay() per iteration: the mark that delimits them.
    EXPECT_EQ(cl.iterations, 1199u);
    EXPECT_EQ(cl.iterations, loop.iterations().size());
    EXPECT_EQ(counts(prof, cl, "delay").calls, cl.iterations);
    Cycles periods = 0;
    for (const auto& it : loop.iterations()) periods += it.period();
    EXPECT_EQ(cl.cycles, periods);
    // Interrupt time as the IsrMonitor measures it from simavr's signals.
    EXPECT_EQ(all.interrupt_cycles, isr.summary().isr_cycles);
    // main runs everything outside interrupts except the start-up code
    // (copying .data, clearing .bss, the constructors: a few thousand cycles).
    const FunctionCounts& main = counts(prof, all, "main");
    EXPECT_EQ(main.calls, 1u);
    const Cycles outside_isr = all.cycles - all.interrupt_cycles;
    EXPECT_LT(main.inclusive_cycles, outside_isr);
    EXPECT_LT(outside_isr - main.inclusive_cycles, 5'000u);
    EXPECT_EQ(counts(prof, cl, "main").inclusive_cycles, cl.cycles - cl.interrupt_cycles);
    // Inclusive >= self for every function; the control loop is a strict
    // subset of the whole run.
    EXPECT_LT(cl.cycles, all.cycles);
    EXPECT_LT(cl.interrupt_cycles, all.interrupt_cycles);
    for (std::size_t id = 0; id < all.functions.size(); ++id) {
        const auto& w = all.functions[id];
        const auto& c = cl.functions[id];
        const auto& name = prof.map().function(static_cast<hil::FunctionId>(id)).name;
        EXPECT_GE(w.inclusive_cycles, w.self_cycles) << name;
        EXPECT_LE(c.self_cycles, w.self_cycles) << name;
        EXPECT_LE(c.inclusive_cycles, w.inclusive_cycles) << name;
        EXPECT_LE(c.calls, w.calls) << name;
    }
    EXPECT_LT(counts(prof, cl, "delay").calls, counts(prof, all, "delay").calls);  // setup()'s delays
    // The call graph: LTO inlined loop() into main, which calls delay() once
    // per iteration, and delay() polls micros().
    expect_consistent(prof, all);
    expect_consistent(prof, cl);
    EXPECT_EQ(edge(prof, cl, "main", "delay").calls, cl.iterations);
    EXPECT_EQ(edge(prof, cl, "delay", "micros").calls, counts(prof, cl, "micros").calls);
    EXPECT_EQ(edge(prof, cl, "delay", "micros").inclusive_cycles, counts(prof, cl, "micros").inclusive_cycles);
    // Nothing executed outside .text; a shallow stack, never overflowed.
    EXPECT_EQ(all.functions[prof.map().outside()].self_cycles, 0u);
    EXPECT_LT(prof.max_depth_seen(), 16u);
    EXPECT_EQ(prof.stack_overflows(), 0u);
    // libm's shared tails (__mulsf3x -> __mulsf3's zero result, __fp_split3
    // -> __fp_splitA's subnormal path): rare, and never counted as calls.
    EXPECT_GT(prof.mid_function_branches(), 0u);
    EXPECT_LT(prof.mid_function_branches(), counts(prof, all, "__mulsf3").calls / 10);
}

}  // namespace
}  // namespace ddmr::test
