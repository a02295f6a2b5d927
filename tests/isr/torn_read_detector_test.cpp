// TornReadDetector: finds the reads of a 32-bit counter that its ISR splits,
// checked against the firmware's own count of inconsistent reads; finds none
// when the read is done with interrupts off; and measures the reference
// sketch's Count1/Count2 reads on closed-loop case 1 (with the ISR table).
//
// torn_counter*.elf (tests/isr/torn_counter.c): TIMER0_OVF every 256 cycles
// stores n * 0x01010101 into `counter`; main copies it in a loop and counts
// reads whose four bytes differ in `inconsistent`. Since every ISR changes
// all four bytes, every split read is visibly torn, so the detector's
// `visible` count must equal `inconsistent`.
#include "hil/torn_read_detector.hpp"

#include <gtest/gtest.h>
#include <sim_avr.h>

#include <array>
#include <iostream>
#include <string>

#include "hil/firmware_report.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/robot_rig.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using hil::atmega328p::vector::kTimer0Ovf;

hil::ElfImage torn_elf(const std::string& variant) {
    auto elf = hil::ElfImage::read(std::string(DDMR_ISR_FIRMWARE_DIR) + "/torn_counter_" + variant + ".elf");
    elf.require_atmega328p();
    return elf;
}

hil::TornReadConfig counter_watch() {
    hil::TornReadConfig c;
    c.variables = {{"counter", {kTimer0Ovf}}};
    return c;
}

struct CounterRun {
    hil::TornReadStats stats;
    std::vector<hil::TornRead> records;
    uint32_t inconsistent = 0;  ///< the firmware's own count
    uint32_t reads = 0;
};

constexpr hil::Cycles kRunCycles = 2'000'000;  // 0.125 s: ~7,800 TIMER0 overflows

CounterRun run_counter(const std::string& variant) {
    const auto elf = torn_elf(variant);
    hil::AvrCore core(elf);
    hil::TornReadDetector detector(core, elf, counter_watch());
    core.run_until(kRunCycles);
    const hil::FirmwareVariables vars(elf, core);
    return CounterRun{detector.stats(), detector.records(), vars.read_u32("inconsistent"), vars.read_u32("reads")};
}

TEST(TornReadDetector, FindsEveryTearOfTheRacyLdsRead) {
    const auto r = run_counter("racy");
    ASSERT_GT(r.reads, 10'000u);
    // At least 100 tears in 2 Mcycles (measured: see the report); every one visible.
    EXPECT_GE(r.stats.torn, 100u);
    EXPECT_EQ(r.stats.visible, r.stats.torn);
    EXPECT_EQ(r.stats.split_reads, r.stats.torn);  // every ISR changes the counter
    // The firmware counts a torn read a few instructions after it: one may be
    // in flight when the run stops.
    EXPECT_LE(r.inconsistent, r.stats.visible);
    EXPECT_GE(r.inconsistent + 1, r.stats.visible);
    for (const auto& t : r.records) {
        EXPECT_EQ(t.vector, kTimer0Ovf);
        // bytes in loaded_before come from value_before, the rest from value_after
        uint64_t expect = 0;
        for (int b = 3; b >= 0; --b) {
            const uint64_t from = ((t.loaded_before >> b) & 1U) != 0 ? t.value_before : t.value_after;
            expect = (expect << 8) | ((from >> (8 * b)) & 0xFF);
        }
        EXPECT_EQ(t.value_read, expect);
        // 4 x LDS low byte first: byte 0, bytes 0-1 or bytes 0-2 were loaded.
        EXPECT_TRUE(t.loaded_before == 0x1 || t.loaded_before == 0x3 || t.loaded_before == 0x7) << +t.loaded_before;
        EXPECT_EQ((t.value_before & 0xFF) * 0x01010101U, t.value_before);  // n * 0x01010101
        EXPECT_EQ(((t.value_before + 1) & 0xFF) * 0x01010101U, t.value_after);  // n + 1 (mod 256)
    }
    std::cout << "racy LDS read: " << r.reads << " reads, " << r.stats.torn << " torn (firmware counted "
              << r.inconsistent << ")\n";
}

TEST(TornReadDetector, FindsTearsOfAReadThroughThePointerZ) {
    const auto r = run_counter("pointer");
    ASSERT_GT(r.reads, 10'000u);
    EXPECT_GE(r.stats.torn, 100u);
    EXPECT_EQ(r.stats.visible, r.stats.torn);
    EXPECT_LE(r.inconsistent, r.stats.visible);
    EXPECT_GE(r.inconsistent + 1, r.stats.visible);
    std::cout << "pointer LD/LDD read: " << r.reads << " reads, " << r.stats.torn << " torn (firmware counted "
              << r.inconsistent << ")\n";
}

TEST(TornReadDetector, FindsNoneWhenTheReadRunsWithInterruptsOff) {
    const auto r = run_counter("atomic");
    ASSERT_GT(r.reads, 10'000u);
    EXPECT_GT(r.stats.entries_checked, 7'000u);  // the ISR ran all along
    EXPECT_EQ(r.stats.split_reads, 0u);
    EXPECT_EQ(r.stats.torn, 0u);
    EXPECT_EQ(r.inconsistent, 0u);
}

TEST(TornReadDetector, DecodesTheLoadsAroundEachResumePoint) {
    const auto elf = torn_elf("racy");
    hil::AvrCore core(elf);
    const auto counter = elf.require("counter");
    const auto main_fn = elf.require("main");
    // The first "lds rN, counter" in main (1001 000d dddd 0000, then k).
    uint32_t first = 0;
    for (uint32_t a = main_fn.address; a < main_fn.address + main_fn.size; a += 2) {
        if ((core.flash_word(a) & 0xFE0F) == 0x9000 && core.flash_word(a + 2) == counter.address) {
            first = a;
            break;
        }
    }
    ASSERT_NE(first, 0u);
    const auto addr = static_cast<uint16_t>(counter.address);
    const hil::PointerRegs regs{};
    // Resume before LDS k (k = 0..4): bytes 0..k-1 loaded, k..3 to load.
    const uint8_t expect_before[5] = {0x0, 0x1, 0x3, 0x7, 0xF};
    for (uint32_t k = 0; k <= 4; ++k) {
        const auto s = hil::find_read_split(core, first + 4 * k, regs, addr, 4);
        EXPECT_EQ(s.before, expect_before[k]) << k;
        EXPECT_EQ(s.after, static_cast<uint8_t>(0xF & ~expect_before[k])) << k;
        EXPECT_EQ(s.split(), k >= 1 && k <= 3) << k;
    }
}

TEST(TornReadDetector, FollowsThePointerOfLdAndLdd) {
    // torn_counter_pointer.elf: lds r30/r31 <- counter_ptr; ld r24,Z;
    // ldd r25,Z+1; ldd r26,Z+2; ldd r27,Z+3.
    const auto elf = torn_elf("pointer");
    hil::AvrCore core(elf);
    const auto counter = elf.require("counter");
    const auto main_fn = elf.require("main");
    uint32_t ld_z = 0;  // "ld r24, Z" = LDD q = 0: 1000 000d dddd 0000
    for (uint32_t a = main_fn.address; a < main_fn.address + main_fn.size; a += 2) {
        if ((core.flash_word(a) & 0xFE0F) == 0x8000) {
            ld_z = a;
            break;
        }
    }
    ASSERT_NE(ld_z, 0u);
    const auto addr = static_cast<uint16_t>(counter.address);
    const hil::PointerRegs z{0, 0, addr};
    const auto mid = hil::find_read_split(core, ld_z + 2, z, addr, 4);
    EXPECT_EQ(mid.before, 0x1);
    EXPECT_EQ(mid.after, 0xE);
    // Before the first LD the walk back meets "lds r31": Z unknown, stop.
    const auto start = hil::find_read_split(core, ld_z, z, addr, 4);
    EXPECT_EQ(start.before, 0x0);
    EXPECT_EQ(start.after, 0xF);
    EXPECT_FALSE(start.split());
}

TEST(TornReadDetector, UndoesPostIncrementAndPreDecrementWalkingBack) {
    const auto elf = torn_elf("racy");
    hil::AvrCore core(elf);
    // Synthetic code in unused flash at 0x7000, then a NOP (not a load).
    const auto put = [&](uint32_t at, std::initializer_list<uint16_t> words) {
        for (const uint16_t w : words) {
            core.raw()->flash[at] = static_cast<uint8_t>(w & 0xFF);
            core.raw()->flash[at + 1] = static_cast<uint8_t>(w >> 8);
            at += 2;
        }
    };
    constexpr uint16_t var = 0x0200;
    // ld r22,X+ / ld r23,X+ / ld r24,X+ / ld r25,X+ (1001 000d dddd 1101), nop
    put(0x7000, {0x916D, 0x917D, 0x918D, 0x919D, 0x0000});
    const auto x = hil::find_read_split(core, 0x7004, hil::PointerRegs{var + 2, 0, 0}, var, 4);
    EXPECT_EQ(x.before, 0x3);  // X+ undone: bytes 1, 0
    EXPECT_EQ(x.after, 0xC);
    // High byte first: ld r25,-Y / ld r24,-Y / ld r23,-Y / ld r22,-Y (1001 000d dddd 1010)
    put(0x7100, {0x919A, 0x918A, 0x917A, 0x916A, 0x0000});
    const auto y = hil::find_read_split(core, 0x7102, hil::PointerRegs{0, var + 3, 0}, var, 4);
    EXPECT_EQ(y.before, 0x8);
    EXPECT_EQ(y.after, 0x7);
    // A load into r26 (part of X) hides X from the loads before it.
    put(0x7200, {0x916D, 0x917D, 0x91AD /* ld r26,X+ */, 0x0000});
    const auto clobbered = hil::find_read_split(core, 0x7206, hil::PointerRegs{var + 3, 0, 0}, var, 4);
    EXPECT_EQ(clobbered.before, 0x0);
}

TEST(TornReadDetector, RejectsAnUnknownOrOneByteVariable) {
    const auto elf = torn_elf("racy");
    hil::AvrCore core(elf);
    hil::TornReadConfig c;
    c.variables = {{"no_such_variable", {}}};
    EXPECT_THROW(hil::TornReadDetector(core, elf, c), std::invalid_argument);
    c.variables = {{"counter", {26}}};
    EXPECT_THROW(hil::TornReadDetector(core, elf, c), std::invalid_argument);
}

// The reference sketch on closed-loop case 1 (as tests/support/rig_run.hpp,
// with the monitor and the detector attached before the boot).
struct Case1 {
    hil::IsrSummary isr;
    std::array<hil::TornReadStats, 2> counts{};  ///< Count1, Count2
    uint64_t checked = 0;
    std::array<uint64_t, 2> encoder_isrs{};
    bool complete = false;
};

Case1 run_case1(bool precise) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::RobotRig rig(elf, hil::RigConfig{});
    hil::IsrMonitor monitor(rig.core(), elf, {precise, 0});
    hil::TornReadDetector detector(rig.core(), elf);  // Count1 <- INT0, Count2 <- INT1
    hil::FirmwareReportParser parser(true);
    rig.uart().set_listener([&](const hil::UartByte& b) {
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (parser.complete() || parser.error()) rig.core().request_stop();
    });
    const auto limit = hil::s_to_cycles(40.0);
    Case1 r;
    if (rig.core().run_until_return_from(elf.require("delay"), limit) != hil::RunStop::kCondition) return r;
    rig.uart().send("1");
    rig.core().run_until(limit);
    r.complete = parser.complete();
    r.isr = monitor.summary();
    r.counts = {detector.stats(0), detector.stats(1)};
    r.checked = detector.stats().entries_checked;
    r.encoder_isrs = {rig.encoders().stats(0).isr_count, rig.encoders().stats(1).isr_count};
    return r;
}

const hil::VectorSummary& find_vector(const hil::IsrSummary& s, int vector) {
    for (const auto& v : s.vectors) {
        if (v.vector == vector) return v;
    }
    throw std::runtime_error("vector " + std::to_string(vector) + " was never entered");
}

TEST(ReferenceFirmwareIsr, Case1IsrTimingAndCountTears) {
    namespace vec = hil::atmega328p::vector;
    const Case1 r = run_case1(false);
    ASSERT_TRUE(r.complete);
    std::cout << hil::to_markdown(r.isr);
    for (std::size_t i = 0; i < 2; ++i) {
        std::cout << "Count" << i + 1 << ": split reads " << r.counts[i].split_reads << ", torn "
                  << r.counts[i].torn << ", visibly torn " << r.counts[i].visible << "\n";
    }

    // Handler lengths are the firmware's (no branches in the encoder path):
    // INT0/INT1 = JMP, WInterrupts.c's ISR (save all call-clobbered registers,
    // ICALL through intFunc), encoder1()/encoder2() (Count++), restore, RETI.
    const auto& int0 = find_vector(r.isr, vec::kInt0);
    const auto& int1 = find_vector(r.isr, vec::kInt1);
    EXPECT_EQ(int0.duration.min, 101u);
    EXPECT_EQ(int0.duration.max, 101u);
    EXPECT_EQ(int1.duration.min, 101u);
    EXPECT_EQ(int1.duration.max, 101u);
    // wiring.c's TIMER0_OVF: 96, or 97 when the millis fraction wraps.
    const auto& t0 = find_vector(r.isr, vec::kTimer0Ovf);
    EXPECT_EQ(t0.handler, "__vector_16");
    EXPECT_EQ(t0.duration.min, 96u);
    EXPECT_EQ(t0.duration.max, 97u);
    EXPECT_EQ(find_vector(r.isr, vec::kUsartRx).count, 1u);  // the case byte
    EXPECT_GT(find_vector(r.isr, vec::kUsartUdre).count, 1000u);
    // Every INT0/INT1 entry is an encoder edge the injector counted.
    EXPECT_EQ(int0.count, r.encoder_isrs[0]);
    EXPECT_EQ(int1.count, r.encoder_isrs[1]);
    EXPECT_EQ(r.checked, int0.count + int1.count);
    // Interrupts are never off for long: a request waits at most for the
    // longest ISR in progress (UDRE, <= 131 cycles), the higher-priority
    // requests pending with it (INT0, INT1: 101 each, for TIMER0_OVF) and a
    // few main-code cli cycles. Measured max: INT0 100, INT1 106, TIMER0_OVF
    // 185 (an INT0 or INT1 served first).
    for (const auto& v : r.isr.vectors) {
        const unsigned higher = v.name == "TIMER0_OVF" ? 2 * 101u : v.name == "INT1" ? 101u : 0u;
        EXPECT_LT(v.latency.max, 160u + higher) << v.name;
    }
    EXPECT_EQ(r.isr.max_nesting, 1);  // no handler re-enables interrupts
    EXPECT_LT(static_cast<double>(r.isr.isr_cycles) / static_cast<double>(r.isr.observed_cycles()), 0.02);

    // Torn reads of Count1/Count2 in loop(): each is 4 x LDS (low byte first,
    // e.g. 0xd70..0xd7c), so an encoder ISR splits a read only if it is
    // entered after the 1st, 2nd or 3rd LDS: a 6-cycle window per read. With
    // ~400 edges/s per wheel and ~100 reads/s that is ~1.5e-4 splits per
    // read, ~0.3 per wheel in a run (measured: Count1 0, Count2 1). A split
    // read is visibly torn only if the increment carries into a byte that is
    // still to load (once in 256 increments for byte 1); otherwise the main
    // code gets the old low byte with unchanged high bytes = the old value,
    // merely stale (Count2's one split read is such a case).
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_LE(r.counts[i].split_reads, 3u) << i;
        EXPECT_LE(r.counts[i].torn, r.counts[i].split_reads) << i;
        EXPECT_EQ(r.counts[i].visible, 0u) << i;
    }
}

// Precise mode: the reference run with SREG.I looked at after every
// instruction (slower: several seconds more).
TEST(ReferenceFirmwareIsr, Case1CyclesWithInterruptsDisabled) {
    const Case1 r = run_case1(true);
    ASSERT_TRUE(r.complete);
    ASSERT_TRUE(r.isr.interrupts_disabled_cycles.has_value());
    const auto disabled = *r.isr.interrupts_disabled_cycles;
    std::cout << "observed " << r.isr.observed_cycles() << " cycles, in ISRs " << r.isr.isr_cycles
              << ", interrupts disabled " << disabled << "\n";
    EXPECT_GE(disabled, r.isr.isr_cycles);
    // Measured 54.3 M of 313.4 M cycles (17.3 %), 16x the ISR time: the main
    // code's cli sections, above all micros() (cli ... SREG = oldSREG around
    // reading timer0_overflow_count and TCNT0), which delay() calls back to
    // back while it waits out the loop's delay(9).
    const double share = static_cast<double>(disabled) / static_cast<double>(r.isr.observed_cycles());
    EXPECT_GT(share, 0.10);
    EXPECT_LT(share, 0.25);
}

}  // namespace
}  // namespace ddmr::test
