// PhaseCorrectTimer: a timer in a phase-correct PWM mode that simavr 1.6
// lacks raises its flags and counts as the ATmega328P datasheet times it
// (7810D §15.9.4, §17.7.4: the count runs 0..TOP..0, one period 2·TOP·N
// cycles; TOVn at BOTTOM, OCFnx where the count reaches OCRnx up and down,
// ICF1 at TOP when ICR1 is TOP). pc_timer_fixture.c enables every one of the
// timer's interrupts and sleeps; the test records when each is raised.
#include "hil/phase_correct_timer.hpp"

#include <gtest/gtest.h>

#include <sim_avr.h>
#include <sim_interrupts.h>
#include <sim_irq.h>

#include <map>
#include <string>
#include <vector>

#include "support/test_paths.hpp"

namespace ddmr::hil {
namespace {

// ATmega328P vector numbers (datasheet Table 11-1).
constexpr int kTimer2CompA = 7, kTimer2CompB = 8, kTimer2Ovf = 9;
constexpr int kTimer1Capt = 10, kTimer1CompA = 11, kTimer1CompB = 12, kTimer1Ovf = 13;
constexpr int kTimer0Ovf = 16;

/// Raise cycles per vector, from simavr's PENDING IRQ.
struct Raises {
    struct Hook {
        Raises* self;
        int vector;
        avr_t* avr;
    };
    std::map<int, std::vector<Cycles>> at;
    std::vector<Hook> hooks;

    Raises(avr_t* avr, const std::vector<int>& vectors) {
        hooks.reserve(vectors.size());
        for (int v : vectors) {
            hooks.push_back({this, v, avr});
            avr_irq_register_notify(avr_get_interrupt_irq(avr, static_cast<uint8_t>(v)) + AVR_INT_IRQ_PENDING,
                                    &Raises::on_pending, &hooks.back());
        }
    }
    static void on_pending(avr_irq_t* /*irq*/, uint32_t value, void* param) {
        auto* h = static_cast<Hook*>(param);
        if (value != 0) h->self->at[h->vector].push_back(h->avr->cycle);
    }
    /// The raises of `vector` as cycles after `origin`, within one period.
    std::vector<Cycles> phases(int vector, Cycles origin, Cycles period) const {
        std::vector<Cycles> out;
        auto it = at.find(vector);
        if (it == at.end()) return out;
        for (Cycles c : it->second) {
            if (c >= origin && c < origin + period) out.push_back(c - origin);
        }
        return out;
    }
};

struct Fixture {
    explicit Fixture(const std::string& name)
        : elf(ElfImage::read(test::test_firmware_dir() / (name + ".elf"))), core(elf), timers(core) {}
    ElfImage elf;
    AvrCore core;
    PhaseCorrectTimers timers;
};

/// Each overflow comes `period` after the one before, and each vector of
/// `phases` is raised at those cycles after each overflow (one period's
/// worth); returns the overflows' cycles.
std::vector<Cycles> expect_schedule(Raises& r, int overflow, Cycles period,
                                    const std::map<int, std::vector<Cycles>>& phases) {
    const std::vector<Cycles> ovf = r.at[overflow];
    EXPECT_GE(ovf.size(), 5U);
    for (std::size_t i = 1; i < ovf.size(); ++i) EXPECT_EQ(ovf[i] - ovf[i - 1], period) << i;
    for (std::size_t i = 0; i + 1 < ovf.size(); ++i) {
        for (const auto& [vector, expected] : phases) EXPECT_EQ(r.phases(vector, ovf[i], period), expected) << vector << " " << i;
    }
    return ovf;
}

/// TCNTn as the firmware reads it now (through the register's read handler).
uint16_t read_tcnt(AvrCore& core, const TimerDesc& d) {
    avr_t* avr = core.raw();
    auto& io = avr->io[AVR_DATA_TO_IO(d.tcnt_low)];
    uint16_t v = io.r.c(avr, d.tcnt_low, io.r.param);
    if (d.tcnt_high != 0) v = static_cast<uint16_t>(v | (avr->data[d.tcnt_high] << 8));
    return v;
}

/// The 0..top..0 triangle `cycles` after BOTTOM, N cycles per count.
uint16_t triangle(Cycles cycles, Cycles top, Cycles n) {
    const Cycles k = (cycles % (2 * top * n)) / n;
    return static_cast<uint16_t>(k <= top ? k : 2 * top - k);
}

TEST(PhaseCorrectTimer, Timer1Mode1RaisesAtTheDatasheetCycles) {
    // TOP 255, N 64: period 32,640; OCR1A = 100 matches 6,400 after BOTTOM
    // counting up and 32,640 - 6,400 = 26,240 counting down; OCR1B = TOP
    // once, at 255 * 64 = 16,320. simavr alone: TOV1 every 64 cycles.
    Fixture f("pc_timer_t1_mode1");
    Raises r(f.core.raw(), {kTimer1Ovf, kTimer1CompA, kTimer1CompB, kTimer1Capt});
    f.core.run_until(200'000);
    EXPECT_TRUE(f.timers.timer(1).active());
    const std::vector<Cycles> ovf =
        expect_schedule(r, kTimer1Ovf, 32'640, {{kTimer1CompA, {6'400, 26'240}}, {kTimer1CompB, {16'320}}});
    ASSERT_FALSE(ovf.empty());
    EXPECT_TRUE(r.at[kTimer1Capt].empty());  // ICR1 is not TOP in mode 1
    // The count: a raise is served when simavr wakes, one cycle after it
    // (sim_avr.c: cycle += 1 + sleep), so BOTTOM was ovf[0] - 1. Read it
    // half a count into several counts, up and down.
    const Cycles bottom = ovf.back() - 1;
    const TimerDesc& d = f.core.mcu().timers[1];
    for (Cycles into : {Cycles{32}, Cycles{64 * 100 + 32}, Cycles{64 * 255 + 32}, Cycles{64 * 300 + 32},
                        Cycles{32'640 - 32}}) {
        f.core.run_until(bottom + into);
        EXPECT_EQ(read_tcnt(f.core, d), triangle(f.core.cycle() - bottom, 255, 64)) << into;
    }
}

TEST(PhaseCorrectTimer, Timer2Mode1RaisesAtTheDatasheetCycles) {
    // OCR2A = 200: 12,800 and 32,640 - 12,800 = 19,840; OCR2B = BOTTOM:
    // once, with TOV2.
    Fixture f("pc_timer_t2_mode1");
    Raises r(f.core.raw(), {kTimer2Ovf, kTimer2CompA, kTimer2CompB});
    f.core.run_until(200'000);
    EXPECT_TRUE(f.timers.timer(2).active());
    (void)expect_schedule(r, kTimer2Ovf, 32'640, {{kTimer2CompA, {12'800, 19'840}}, {kTimer2CompB, {0}}});
}

TEST(PhaseCorrectTimer, Timer1Mode10TakesTopFromIcr1) {
    // TOP = ICR1 = 1000, N = 8: period 16,000; OCR1A = 250: 2,000 and
    // 14,000; OCR1B = TOP and ICF1: 8,000.
    Fixture f("pc_timer_t1_mode10");
    Raises r(f.core.raw(), {kTimer1Ovf, kTimer1CompA, kTimer1CompB, kTimer1Capt});
    f.core.run_until(120'000);
    const std::vector<Cycles> ovf = expect_schedule(
        r, kTimer1Ovf, 16'000, {{kTimer1CompA, {2'000, 14'000}}, {kTimer1CompB, {8'000}}, {kTimer1Capt, {8'000}}});
    ASSERT_FALSE(ovf.empty());
    const Cycles bottom = ovf.back() - 1;
    const TimerDesc& d = f.core.mcu().timers[1];
    for (Cycles into : {Cycles{4}, Cycles{8 * 999 + 4}, Cycles{8 * 1001 + 4}, Cycles{16'000 - 4}}) {
        f.core.run_until(bottom + into);
        EXPECT_EQ(read_tcnt(f.core, d), triangle(f.core.cycle() - bottom, 1000, 8)) << into;
    }
}

/// The intervals between the raises of `vector` inside [from, to).
std::vector<Cycles> intervals(Raises& r, int vector, Cycles from, Cycles to) {
    std::vector<Cycles> in;
    for (Cycles c : r.at[vector]) {
        if (c >= from && c < to) in.push_back(c);
    }
    std::vector<Cycles> out;
    for (std::size_t i = 1; i < in.size(); ++i) out.push_back(in[i] - in[i - 1]);
    return out;
}

TEST(PhaseCorrectTimer, HandsTheTimerBackAndTakesItAgainAsTheModeChanges) {
    // PC_T2_CHANGES: Timer2 at clk/64, OCR2A = 99: WGM 1 (taken over: TOV2
    // every 32,640 cycles, OCF2A 99 * 64 = 6,336 after BOTTOM and 6,336
    // before the next), CTC (simavr's: OCF2A every 100 * 64 = 6,400; simavr
    // 1.6 also raises TOV2 there, which the chip does not: not this part's),
    // WGM 1 again (taken over again), then ASSR.AS2 (simavr's).
    Fixture f("pc_timer_t2_changes");
    Raises r(f.core.raw(), {kTimer2Ovf, kTimer2CompA});
    std::vector<Cycles> changes;  // when active() changed, to a 100-cycle step
    bool active = false;
    for (Cycles c = 100; c <= 600'000; c += 100) {
        f.core.run_until(c);
        if (f.timers.timer(2).active() != active) {
            active = !active;
            changes.push_back(c);
        }
    }
    ASSERT_EQ(changes.size(), 4U);  // on, off (CTC), on, off (AS2)
    const std::vector<Cycles> ovf = r.at[kTimer2Ovf];
    ASSERT_FALSE(ovf.empty());
    EXPECT_EQ(r.phases(kTimer2CompA, ovf[0] - 1, 32'640), (std::vector<Cycles>{6'336 + 1, 26'304 + 1}));
    EXPECT_EQ(intervals(r, kTimer2Ovf, changes[0], changes[1]), std::vector<Cycles>(3, 32'640));
    const std::vector<Cycles> ctc = intervals(r, kTimer2CompA, changes[1] + 100, changes[2]);
    ASSERT_GE(ctc.size(), 6U);
    for (std::size_t i = 1; i < ctc.size(); ++i) EXPECT_EQ(ctc[i], 6'400U) << i;
    EXPECT_EQ(intervals(r, kTimer2Ovf, changes[2], changes[3]), std::vector<Cycles>(3, 32'640));
}

TEST(PhaseCorrectTimer, LeavesTheModesSimavrRunsToSimavr) {
    // The reference firmware after the Arduino core's init(): Timer0 in fast
    // PWM (mode 3, in simavr's table) stays simavr's, its overflow every
    // 256 * 64 = 16,384 cycles as before; Timer1 and Timer2 in WGM 1 are
    // taken over.
    const ElfImage elf = ElfImage::read(test::firmware_elf());
    AvrCore core(elf);
    PhaseCorrectTimers timers(core);
    Raises r(core.raw(), {kTimer0Ovf});
    core.run_until(100'000);
    EXPECT_FALSE(timers.timer(0).active());
    EXPECT_TRUE(timers.timer(1).active());
    EXPECT_TRUE(timers.timer(2).active());
    const std::size_t before = r.at[kTimer0Ovf].size();
    core.run_until(100'000 + 100 * 16'384);
    EXPECT_NEAR(static_cast<double>(r.at[kTimer0Ovf].size() - before), 100.0, 1.0);
    EXPECT_FALSE(timers.timer(0).takes_over(3));
    EXPECT_FALSE(timers.timer(1).takes_over(8));  // PFC: in simavr's table
    for (std::size_t n = 0; n < 3; ++n) EXPECT_TRUE(timers.timer(n).takes_over(1)) << n;
}

}  // namespace
}  // namespace ddmr::hil
