// RaceDetector: finds the reads of a 32-bit counter that its ISR splits,
// checked against the firmware's own count of inconsistent reads; finds none
// when the read is done with interrupts off; finds the planted torn read,
// torn write and stale read of race_fixture.c and nothing in its fixed
// build; and measures the reference sketch's Count1/Count2 reads on
// closed-loop case 1 (with the ISR table).
//
// torn_counter*.elf (tests/isr/torn_counter.c): TIMER0_OVF every 256 cycles
// stores n * 0x01010101 into `counter`; main copies it in a loop and counts
// reads whose four bytes differ in `inconsistent`. Since every ISR changes
// all four bytes, every split read is visibly torn, so the detector's
// `observed` count must equal `inconsistent`.
#include "hil/race_detector.hpp"

#include <gtest/gtest.h>
#include <sim_avr.h>

#include <array>
#include <map>
#include <iostream>
#include <string>

#include "hil/avr_decode.hpp"
#include "hil/firmware_report.hpp"
#include "hil/firmware_variables.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/robot_rig.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using hil::atmega328p::vector::kTimer0Ovf;

hil::ElfImage isr_elf(const std::string& name) {
    auto elf = hil::ElfImage::read(std::string(DDMR_ISR_FIRMWARE_DIR) + "/" + name + ".elf");
    elf.require_mcu(hil::atmega328p_mcu());
    return elf;
}

/// tests/firmware's fixtures (race_fixture.c).
hil::ElfImage fixture_elf(const std::string& name, const hil::McuDescription& mcu = hil::atmega328p_mcu()) {
    auto elf = hil::ElfImage::read(test_firmware_dir() / (name + ".elf"));
    elf.require_mcu(mcu);
    return elf;
}

hil::ElfImage torn_elf(const std::string& variant) { return isr_elf("torn_counter_" + variant); }

/// A split access's counts, summed over the accesses of one variable and kind.
struct Counts {
    uint64_t splits = 0;    ///< by an ISR that shares the variable
    uint64_t torn = 0;
    uint64_t observed = 0;
    std::vector<hil::SplitAccess> accesses;  ///< copies (the detector is gone after the run)
};

Counts counts(const hil::RaceDetector& d, const std::string& name, hil::AccessKind kind) {
    Counts c;
    const auto o = d.objects().find(name);
    if (!o) return c;
    for (const auto& a : d.splits()) {
        if (a.object != *o || a.kind != kind || !d.is_race(a)) continue;
        c.splits += d.race_splits(a);
        c.torn += a.torn;
        c.observed += a.observed;
        c.accesses.push_back(a);
    }
    return c;
}

struct CounterRun {
    Counts read;
    uint64_t entries = 0;
    uint32_t inconsistent = 0;  ///< the firmware's own count
    uint32_t reads = 0;
};

constexpr hil::Cycles kRunCycles = 2'000'000;  // 0.125 s: ~7,800 TIMER0 overflows

CounterRun run_counter(const std::string& variant) {
    const auto elf = torn_elf(variant);
    hil::AvrCore core(elf);
    hil::RaceDetector detector(core, elf);
    core.run_until(kRunCycles);
    const hil::FirmwareVariables vars(elf, core);
    return CounterRun{counts(detector, "counter", hil::AccessKind::kRead), detector.stats().entries_checked,
                      vars.read_u32("inconsistent"), vars.read_u32("reads")};
}

TEST(RaceDetector, FindsEveryTearOfTheRacyLdsRead) {
    const auto r = run_counter("racy");
    ASSERT_GT(r.reads, 10'000u);
    // At least 100 tears in 2 Mcycles (measured: see the report); every one visible.
    EXPECT_GE(r.read.torn, 100u);
    EXPECT_EQ(r.read.observed, r.read.torn);
    EXPECT_EQ(r.read.splits, r.read.torn);  // every ISR changes the counter
    // The firmware counts a torn read a few instructions after it: one may be
    // in flight when the run stops.
    EXPECT_LE(r.inconsistent, r.read.observed);
    EXPECT_GE(r.inconsistent + 1, r.read.observed);
    // One access (main's 4 x LDS), split only by TIMER0_OVF; its example is
    // n * 0x01010101 -> (n + 1) * 0x01010101 with a mix in between.
    ASSERT_EQ(r.read.accesses.size(), 1u);
    const hil::SplitAccess& a = r.read.accesses[0];
    EXPECT_EQ(a.splits[kTimer0Ovf], a.total_splits());
    EXPECT_EQ((a.example_before & 0xFF) * 0x01010101U, a.example_before);
    EXPECT_EQ(((a.example_before + 1) & 0xFF) * 0x01010101U, a.example_after);
    EXPECT_NE(a.example_seen, a.example_before);
    EXPECT_NE(a.example_seen, a.example_after);
    for (int b = 0; b < 4; ++b) {  // every byte of what was read comes from before or after
        const uint64_t m = 0xFFULL << (8 * b);
        EXPECT_TRUE((a.example_seen & m) == (a.example_before & m) || (a.example_seen & m) == (a.example_after & m));
    }
    std::cout << "racy LDS read: " << r.reads << " reads, " << r.read.torn << " torn (firmware counted "
              << r.inconsistent << ")\n";
}

TEST(RaceDetector, FindsTearsOfAReadThroughThePointerZ) {
    const auto r = run_counter("pointer");
    ASSERT_GT(r.reads, 10'000u);
    EXPECT_GE(r.read.torn, 100u);
    EXPECT_EQ(r.read.observed, r.read.torn);
    EXPECT_LE(r.inconsistent, r.read.observed);
    EXPECT_GE(r.inconsistent + 1, r.read.observed);
    std::cout << "pointer LD/LDD read: " << r.reads << " reads, " << r.read.torn << " torn (firmware counted "
              << r.inconsistent << ")\n";
}

TEST(RaceDetector, FindsNoneWhenTheReadRunsWithInterruptsOff) {
    const auto r = run_counter("atomic");
    ASSERT_GT(r.reads, 10'000u);
    EXPECT_GT(r.entries, 7'000u);  // the ISR ran all along
    EXPECT_EQ(r.read.splits, 0u);
    EXPECT_EQ(r.read.torn, 0u);
    EXPECT_EQ(r.inconsistent, 0u);
}

TEST(RaceDetector, DecodesTheLoadsAroundEachResumePoint) {
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

TEST(RaceDetector, FollowsThePointerOfLdAndLdd) {
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

TEST(RaceDetector, UndoesPostIncrementAndPreDecrementWalkingBack) {
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

// --- race_fixture.c: a torn read, a torn write and a stale read, then fixed ---

struct FixtureRun {
    Counts ticks_read, setpoint_write;
    std::vector<hil::StaleRead> stale;
    std::vector<hil::SharedVariable> shared;
    std::string names;  ///< "name:writers:readers " per shared variable
    uint8_t done = 0;
};

/// `elf_name`: race_fixture_racy / _fixed (ATmega328P), race_fixture_atmega2560 (racy).
FixtureRun run_fixture(const std::string& elf_name, hil::BoardModel board = hil::BoardModel::uno) {
    hil::AvrCoreConfig config;
    config.board = board;
    const auto elf = fixture_elf(elf_name, *hil::board_description(board).mcu);
    hil::AvrCore core(elf, config);
    hil::RaceDetector detector(core, elf);
    core.run_until(kRunCycles);
    FixtureRun r;
    r.ticks_read = counts(detector, "ticks", hil::AccessKind::kRead);
    r.setpoint_write = counts(detector, "setpoint", hil::AccessKind::kWrite);
    r.stale = detector.stale_reads();
    r.shared = detector.shared();
    for (const auto& s : r.shared) {
        r.names += detector.objects()[s.object].name + ":" + std::to_string(s.isr_writers) + ":" +
                   std::to_string(s.isr_readers) + " ";
    }
    const hil::FirmwareVariables vars(elf, core);
    r.done = vars.read_u8("done");
    return r;
}

/// The three races race_fixture.c plants, found; `t0`: TIMER0_OVF's vector bit.
void expect_planted_races(const FixtureRun& r, hil::VectorMask t0) {
    // Shared variables, found by stepping the ISR: what TIMER0_OVF writes and reads.
    const std::string expect_shared = "ticks:" + std::to_string(t0) + ":" + std::to_string(t0);
    EXPECT_NE(r.names.find(expect_shared), std::string::npos) << r.names;
    EXPECT_NE(r.names.find("setpoint:0:" + std::to_string(t0)), std::string::npos) << r.names;
    EXPECT_NE(r.names.find("flag:" + std::to_string(t0) + ":0"), std::string::npos) << r.names;
    // The 4 x LDS read of `ticks` (+100 per ISR: carries cross bytes): torn, observed.
    EXPECT_GE(r.ticks_read.splits, 50u);
    EXPECT_GT(r.ticks_read.observed, 0u);
    ASSERT_EQ(r.ticks_read.accesses.size(), 1u);
    // The 2 x STS write of `setpoint` (i * 0x0101: both bytes change): the ISR
    // reads it mid-write, and sees a value other than the one being written.
    EXPECT_GE(r.setpoint_write.splits, 50u);
    EXPECT_EQ(r.setpoint_write.torn, r.setpoint_write.splits);  // the ISR reads it on every entry
    EXPECT_GT(r.setpoint_write.observed, 0u);
    // The non-volatile flag: one LDS, then `rjmp .-2` while TIMER0_OVF writes it.
    ASSERT_EQ(r.stale.size(), 1u);
    EXPECT_EQ(r.stale[0].vectors, t0);
    EXPECT_GT(r.stale[0].writes_missed, 1000u);  // every overflow from the 10th after `armed`
    EXPECT_EQ(r.stale[0].where.loop_begin, r.stale[0].where.loop_end);  // rjmp .-2
    EXPECT_EQ(r.done, 0);  // the firmware is stuck, as on the chip
}

TEST(RaceDetector, FindsThePlantedTornReadTornWriteAndStaleRead) {
    expect_planted_races(run_fixture("race_fixture_racy"), hil::VectorMask{1} << kTimer0Ovf);
}

// The same program on the ATmega2560: 3-byte return addresses on the stack
// (the resume point of each interrupt is read with them), TIMER0_OVF is
// vector 23 (datasheet 2549Q, table 14-1).
TEST(RaceDetector, FindsThePlantedRacesOnTheAtmega2560) {
    ASSERT_STREQ(hil::atmega2560_mcu().vector_name(23).c_str(), "TIMER0_OVF");
    expect_planted_races(run_fixture("race_fixture_atmega2560", hil::BoardModel::mega2560), hil::VectorMask{1} << 23);
}

TEST(RaceDetector, ReportsNothingForTheFixedFirmware) {
    const FixtureRun r = run_fixture("race_fixture_fixed");
    EXPECT_EQ(r.done, 1);  // volatile flag: the loop saw the ISR's write and ended
    EXPECT_EQ(r.ticks_read.splits, 0u);
    EXPECT_EQ(r.setpoint_write.splits, 0u);
    EXPECT_TRUE(r.stale.empty());
    EXPECT_NE(r.names.find("flag:"), std::string::npos) << r.names;  // still shared, safely
}

TEST(RaceDetector, FindsTheStaleLoopInTheCode) {
    const auto elf = fixture_elf("race_fixture_racy");
    hil::AvrCore core(elf);
    const hil::DataObjects objects(elf, hil::atmega328p_mcu());
    const auto main_fn = elf.require("main");
    // The endless `rjmp .-2` (0xCFFF) after the LDS of flag.
    uint32_t spin = 0;
    for (uint32_t a = main_fn.address; a < main_fn.address + main_fn.size; a += 2) {
        if (core.flash_word(a) == 0xCFFF) {
            spin = a;
            break;
        }
    }
    ASSERT_NE(spin, 0u);
    const auto s = hil::find_stale_loop(core, objects, spin);
    ASSERT_TRUE(s.has_value());
    EXPECT_EQ(objects[s->object].name, "flag");
    EXPECT_EQ(core.flash_word(s->load_pc + 2), elf.require("flag").address);  // LDS rN, flag
    // The fixed build re-reads flag inside the loop: no stale loop anywhere in main.
    const auto fixed = fixture_elf("race_fixture_fixed");
    hil::AvrCore fixed_core(fixed);
    const hil::DataObjects fixed_objects(fixed, hil::atmega328p_mcu());
    const auto fixed_main = fixed.require("main");
    for (uint32_t a = fixed_main.address; a < fixed_main.address + fixed_main.size; a += 2) {
        const auto f = hil::find_stale_loop(fixed_core, fixed_objects, a);
        EXPECT_FALSE(f.has_value() && fixed_objects[f->object].name == "flag") << std::hex << a;
    }
}

TEST(AvrDecode, ClassifiesLoadsStoresFlowAndRegisters) {
    namespace avr = hil::avr;
    // sts 0x0106, r24 = 0x9380 0x0106; lds r25, 0x0103 = 0x9190 0x0103
    const auto st = avr::decode_data_access(0x9380, 0x0106);
    ASSERT_TRUE(st.has_value());
    EXPECT_TRUE(st->store);
    EXPECT_EQ(st->k, 0x0106);
    EXPECT_EQ(st->reg, 24);
    EXPECT_EQ(st->words, 2u);
    const auto ld = avr::decode_data_access(0x9190, 0x0103);
    ASSERT_TRUE(ld.has_value());
    EXPECT_FALSE(ld->store);
    EXPECT_EQ(ld->reg, 25);
    // std Y+5, r24 = 10q0 qq1r rrrr 1qqq with q = 5: 1000 0011 1000 1101 = 0x838D
    const auto sd = avr::decode_data_access(0x838D, 0);
    ASSERT_TRUE(sd.has_value());
    EXPECT_TRUE(sd->store);
    EXPECT_EQ(sd->pointer, avr::Pointer::kY);
    EXPECT_EQ(sd->q, 5);
    // rjmp .-2 at 0x17e jumps to itself; brne .-82 at 0x16e goes to 0x11e.
    EXPECT_EQ(avr::decode_flow(0xCFFF, 0, 0x17E).kind, avr::Flow::Kind::kJump);
    EXPECT_EQ(*avr::decode_flow(0xCFFF, 0, 0x17E).target, 0x17Eu);
    EXPECT_EQ(*avr::decode_flow(0xF6B9, 0, 0x16E).target, 0x11Eu);
    EXPECT_EQ(avr::decode_flow(0x1191, 0, 0).kind, avr::Flow::Kind::kSkip);  // cpse r25, r1
    EXPECT_EQ(avr::decode_flow(0x9518, 0, 0).kind, avr::Flow::Kind::kReturn);  // reti
    // call 0x0040 (word 0x20): 1001 0100 0000 1110, 0x0020
    EXPECT_EQ(avr::decode_flow(0x940E, 0x0020, 0).kind, avr::Flow::Kind::kCall);
    EXPECT_EQ(*avr::decode_flow(0x940E, 0x0020, 0).target, 0x40u);
    EXPECT_EQ(avr::instruction_words(0x940E), 2u);
    // cpse r25, r1 reads both, writes none; eor r1, r1 (clr) reads none; ldi r24 writes r24.
    const auto cpse = avr::register_use(0x1191);
    EXPECT_EQ(cpse.reads, (1U << 25) | (1U << 1));
    EXPECT_EQ(cpse.writes, 0u);
    EXPECT_EQ(avr::register_use(0x2411).reads, 0u);
    EXPECT_EQ(avr::register_use(0xE081).writes, 1U << 24);
    EXPECT_FALSE(avr::register_use(0x940E).known);  // a call
    EXPECT_TRUE(avr::reads_data_memory(0xB185));     // in r24, 0x05
    EXPECT_FALSE(avr::reads_data_memory(0x9380));    // sts
}

// The reference sketch on closed-loop case 1 (as tests/support/rig_run.hpp,
// with the monitor and the detector attached before the boot).
struct Case1 {
    hil::IsrSummary isr;
    std::array<Counts, 2> counts{};  ///< Count1, Count2
    std::map<std::string, std::pair<uint32_t, uint32_t>> shared;  ///< writers, readers
    std::size_t stale = 0;
    uint64_t checked = 0;
    std::array<uint64_t, 2> encoder_isrs{};
    bool complete = false;
};

Case1 run_case1(bool precise) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::RobotRig rig(elf, hil::RigConfig{});
    hil::IsrMonitor monitor(rig.core(), elf, {precise, 0});
    hil::RaceDetector detector(rig.core(), elf);
    hil::FirmwareReportParser parser(true);
    rig.uart().set_listener([&](const hil::UartByte& b) {
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (parser.complete() || parser.error()) rig.core().request_stop();
    });
    const auto limit = hil::s_to_cycles(40.0, kUnoClockHz);
    Case1 r;
    if (rig.core().run_until_return_from(elf.require("delay"), limit) != hil::RunStop::kCondition) return r;
    rig.uart().send("1");
    rig.core().run_until(limit);
    r.complete = parser.complete();
    r.isr = monitor.summary();
    r.counts = {counts(detector, "Count1", hil::AccessKind::kRead), counts(detector, "Count2", hil::AccessKind::kRead)};
    r.checked = detector.stats().entries_checked;
    for (const auto& s : detector.shared()) {
        r.shared[detector.objects()[s.object].name] = {s.isr_writers, s.isr_readers};
    }
    r.stale = detector.stale_reads().size();
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
        std::cout << "Count" << i + 1 << ": split reads " << r.counts[i].splits << ", torn " << r.counts[i].torn
                  << ", visibly torn " << r.counts[i].observed << "\n";
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
    uint64_t entries = 0;  // no nesting: every entry interrupts the main program
    for (const auto& v : r.isr.vectors) entries += v.count;
    EXPECT_EQ(r.checked, entries);
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
        EXPECT_LE(r.counts[i].splits, 3u) << i;
        EXPECT_LE(r.counts[i].torn, r.counts[i].splits) << i;
        EXPECT_EQ(r.counts[i].observed, 0u) << i;
    }
    // The race report names Count1/Count2: written by the encoder ISRs
    // (attachInterrupt's ICALL into encoder1()/encoder2(), seen by stepping).
    ASSERT_EQ(r.shared.count("Count1"), 1u);
    ASSERT_EQ(r.shared.count("Count2"), 1u);
    EXPECT_EQ(r.shared.at("Count1").first, 1U << vec::kInt0);
    EXPECT_EQ(r.shared.at("Count2").first, 1U << vec::kInt1);
    // millis()/micros()'s counters: written by TIMER0_OVF (wiring.c).
    ASSERT_EQ(r.shared.count("timer0_overflow_count"), 1u);
    EXPECT_EQ(r.shared.at("timer0_overflow_count").first, 1U << vec::kTimer0Ovf);
    EXPECT_EQ(r.stale, 0u);  // loop() re-reads everything it polls
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
