// LoopPass: what an instruction touches and which bytes a pass carries,
// checked on hand-encoded instructions (AVR Instruction Set Manual,
// DS40002198A: each word below is assembled by hand from its encoding).
#include "hil/loop_pass.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace ddmr::hil {
namespace {

// Encodings (d = destination register, A = I/O address, k = constant).
constexpr uint16_t kLdsR24 = 0x9180;     // LDS r24, k (k in the next word)
constexpr uint16_t kStsR24 = 0x9380;     // STS k, r24
constexpr uint16_t kSubiR24 = 0x5F8F;    // SUBI r24, 0xFF (r24 += 1)
constexpr uint16_t kInR18Tcnt0 = 0xB526;  // IN r18, 0x26 (TCNT0, data 0x46)
constexpr uint16_t kCpiR18 = 0x3624;     // CPI r18, 100
constexpr uint16_t kBrlo = 0xF3E8;       // BRLO .-6 (BRBS 0: reads C)
constexpr uint16_t kRjmpBack = 0xCFFB;   // RJMP .-10
constexpr uint16_t kInR0Sreg = 0xB60F;   // IN r0, SREG
constexpr uint16_t kOutSregR0 = 0xBE0F;  // OUT SREG, r0
constexpr uint16_t kCli = 0x94F8;        // BCLR 7
constexpr uint16_t kCall = 0x940E;       // CALL k
constexpr uint16_t kRet = 0x9508;
constexpr uint16_t kPushR16 = 0x930F;
constexpr uint16_t kPopR16 = 0x910F;
constexpr uint16_t kLdR24XPlus = 0x918D;  // LD r24, X+
constexpr uint16_t kIncR24 = 0x9583;      // INC r24
constexpr uint16_t kSleep = 0x9588;

struct Cpu {
    std::array<uint8_t, 0x900> data{};
    CpuView view(uint16_t sp) {
        CpuView v;
        v.data = data.data();
        v.sp = sp;
        return v;
    }
};

TEST(StepAccess, CallPushesTheReturnAddressBelowSp) {
    Cpu cpu;
    const StepAccess a = step_access(kCall, 0x0100, cpu.view(0x08FF));
    EXPECT_TRUE(a.sp_rw);
    EXPECT_TRUE(a.mem_write);
    ASSERT_EQ(a.count, 2);
    EXPECT_EQ(a.address[0], 0x08FF);
    EXPECT_EQ(a.address[1], 0x08FE);
    EXPECT_EQ(a.refusal, nullptr);
}

TEST(StepAccess, RetPopsAboveSpAndPushPopUseOneByte) {
    Cpu cpu;
    const StepAccess ret = step_access(kRet, 0, cpu.view(0x08FD));
    EXPECT_TRUE(ret.mem_read);
    ASSERT_EQ(ret.count, 2);
    EXPECT_EQ(ret.address[0], 0x08FE);
    EXPECT_EQ(ret.address[1], 0x08FF);
    const StepAccess push = step_access(kPushR16, 0, cpu.view(0x08FF));
    EXPECT_EQ(push.reg_reads, 1U << 16);
    ASSERT_EQ(push.count, 1);
    EXPECT_EQ(push.address[0], 0x08FF);
    const StepAccess pop = step_access(kPopR16, 0, cpu.view(0x08FE));
    EXPECT_EQ(pop.reg_writes, 1U << 16);
    EXPECT_EQ(pop.address[0], 0x08FF);
}

TEST(StepAccess, InAndOutOfSregAreFlagsNotMemory) {
    Cpu cpu;
    const StepAccess in = step_access(kInR0Sreg, 0, cpu.view(0x08FF));
    EXPECT_EQ(in.flag_reads, 0xFF);
    EXPECT_EQ(in.count, 0);
    EXPECT_EQ(in.reg_writes, 1U);
    const StepAccess out = step_access(kOutSregR0, 0, cpu.view(0x08FF));
    EXPECT_EQ(out.flag_writes, 0xFF);
    EXPECT_EQ(out.reg_reads, 1U);
    EXPECT_EQ(step_access(kCli, 0, cpu.view(0x08FF)).flag_writes, 0x80);  // I only
}

TEST(StepAccess, FlagsFollowTheManualsFlagsColumn) {
    Cpu cpu;
    const CpuView v = cpu.view(0x08FF);
    EXPECT_EQ(step_access(kCpiR18, 0, v).flag_writes, 0x3F);  // H S V N Z C
    EXPECT_EQ(step_access(kCpiR18, 0, v).flag_reads, 0);
    EXPECT_EQ(step_access(kIncR24, 0, v).flag_writes, 0x1E);  // S V N Z: C kept
    EXPECT_EQ(step_access(kBrlo, 0, v).flag_reads, 0x01);    // C
    EXPECT_EQ(step_access(0x0B98, 0, v).flag_reads, 0x03);    // SBC r25, r24: C and Z
}

TEST(StepAccess, PointerAccessUsesThePointersValue) {
    Cpu cpu;
    cpu.data[26] = 0x34;  // X = 0x0234
    cpu.data[27] = 0x02;
    const StepAccess a = step_access(kLdR24XPlus, 0, cpu.view(0x08FF));
    ASSERT_EQ(a.count, 1);
    EXPECT_EQ(a.address[0], 0x0234);
    EXPECT_TRUE(a.mem_read);
    EXPECT_EQ(a.reg_writes & (1U << 24), 1U << 24);
}

TEST(StepAccess, SleepRefusesTheLoop) {
    Cpu cpu;
    EXPECT_STREQ(step_access(kSleep, 0, cpu.view(0x08FF)).refusal, "sleeps");
}

std::vector<RecordedStep> record(Cpu& cpu, const std::vector<std::array<uint16_t, 2>>& words) {
    std::vector<RecordedStep> steps;
    uint32_t pc = 0x100;
    for (const auto& w : words) {
        steps.push_back({pc, 0x08FF, step_access(w[0], w[1], cpu.view(0x08FF))});
        pc += 2;
    }
    return steps;
}

TEST(AnalysePass, ACounterInSramIsCarried) {
    // lds r24, 0x0100; subi r24, 0xFF; sts 0x0100, r24; rjmp: n++ in SRAM.
    Cpu cpu;
    const PassAnalysis a = analyse_pass(
        record(cpu, {{kLdsR24, 0x0100}, {kSubiR24, 0}, {kStsR24, 0x0100}, {kRjmpBack, 0}}), 0x20, 0x100, 0x5D);
    EXPECT_EQ(a.carried, std::vector<uint16_t>{0x0100});  // r24 is written before it is read
    EXPECT_EQ(a.carried_flags, 0);
    EXPECT_TRUE(a.refusal.empty());
}

TEST(AnalysePass, ATimerPollCarriesNothing) {
    // in r18, TCNT0; cpi r18, 100; brlo: while (TCNT0 < 100).
    Cpu cpu;
    const PassAnalysis a =
        analyse_pass(record(cpu, {{kInR18Tcnt0, 0}, {kCpiR18, 0}, {kBrlo, 0}}), 0x20, 0x100, 0x5D);
    EXPECT_TRUE(a.carried.empty());
    EXPECT_EQ(a.carried_flags, 0);  // CPI writes C before BRLO reads it
    EXPECT_EQ(a.io_reads, std::vector<uint16_t>{0x46});
    EXPECT_TRUE(a.io_writes.empty());
}

TEST(AnalysePass, ACarryReadBeforeItIsWrittenIsCarried) {
    // brlo (reads C) first, then cpi writes it: C flows from pass to pass.
    Cpu cpu;
    const PassAnalysis a =
        analyse_pass(record(cpu, {{kBrlo, 0}, {kInR18Tcnt0, 0}, {kCpiR18, 0}}), 0x20, 0x100, 0x5D);
    EXPECT_EQ(a.carried_flags, 0x01);
}

TEST(AnalysePass, SavingAndRestoringSregCarriesOnlyWhatIsRead) {
    // in r0, SREG; cli; out SREG, r0: every flag read, then written back.
    Cpu cpu;
    const PassAnalysis a =
        analyse_pass(record(cpu, {{kInR0Sreg, 0}, {kCli, 0}, {kOutSregR0, 0}}), 0x20, 0x100, 0x5D);
    EXPECT_EQ(a.carried_flags, 0xFF);
    EXPECT_TRUE(a.carried.empty());  // r0 written by IN before OUT reads it
}

TEST(AnalysePass, TheFirstRefusalIsReported) {
    Cpu cpu;
    EXPECT_EQ(analyse_pass(record(cpu, {{kInR18Tcnt0, 0}, {kSleep, 0}}), 0x20, 0x100, 0x5D).refusal, "sleeps");
}

TEST(AnalysePass, StackBytesWrittenByACallAreNotCarried) {
    // call f; ... ret (at the same SP): the return address is written first.
    Cpu cpu;
    std::vector<RecordedStep> steps;
    steps.push_back({0x100, 0x08FF, step_access(kCall, 0x0200, cpu.view(0x08FF))});
    steps.push_back({0x400, 0x08FD, step_access(kRet, 0, cpu.view(0x08FD))});
    const PassAnalysis a = analyse_pass(steps, 0x20, 0x100, 0x5D);
    EXPECT_EQ(a.carried, (std::vector<uint16_t>{0x5D, 0x5E}));  // SP: checked equal after the pass
}

}  // namespace
}  // namespace ddmr::hil
