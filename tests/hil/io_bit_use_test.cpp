// IoBitUse: which bits of a PIN register a pass uses, on hand-encoded
// instructions (AVR Instruction Set Manual, DS40002198A; each word checked
// against avr-as). The CPU state is set by hand before each instruction,
// as the instruction before it would have left it.
#include "hil/io_bit_use.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace ddmr::hil {
namespace {

constexpr uint16_t kPind = 0x29;        // data address of PIND (I/O 0x09)
constexpr uint16_t kPinb = 0x23;
constexpr uint16_t kLpmR29Z = 0x91D4;   // LPM r29, Z
constexpr uint16_t kLdR30X = 0x91EC;    // LD r30, X
constexpr uint16_t kAndR30R29 = 0x23ED;  // AND r30, r29
constexpr uint16_t kBrne = 0xF401;      // BRNE .+0 (BRBC 1: reads Z)
constexpr uint16_t kLdiR24One = 0xE081;  // LDI r24, 1
constexpr uint16_t kLdiR24Zero = 0xE080;
constexpr uint16_t kLdiR18Zero = 0xE020;
constexpr uint16_t kInR29Tcnt0 = 0xB5D6;  // IN r29, 0x26
constexpr uint16_t kSbisPind7 = 0x9B4F;   // SBIS 0x09, 7
constexpr uint16_t kInR24Pind = 0xB189;   // IN r24, 0x09
constexpr uint16_t kStsR24 = 0x9380;      // STS k, r24
constexpr uint16_t kAndiR24x0C = 0x708C;  // ANDI r24, 0x0C
constexpr uint16_t kMovR18R24 = 0x2F28;   // MOV r18, r24
constexpr uint16_t kSbrsR18b3 = 0xFF23;   // SBRS r18, 3
constexpr uint16_t kTstR24 = 0x2388;      // AND r24, r24

struct Pass {
    std::array<uint8_t, 0x900> data{};
    IoBitUse use{{kPinb, kPind}, 0x20, 0x100, 0x5D};
    void step(uint16_t w0, uint16_t w1 = 0) {
        CpuView v;
        v.data = data.data();
        v.sp = 0x08FF;
        use.step(w0, step_access(w0, w1, v), v);
    }
    void set_x(uint16_t address) {
        data[26] = static_cast<uint8_t>(address);
        data[27] = static_cast<uint8_t>(address >> 8);
    }
    /// digitalRead()'s load and mask: r29 from flash, PIND through X, AND, BRNE.
    void digital_read(uint8_t mask) {
        step(kLpmR29Z);
        data[29] = mask;
        set_x(kPind);
        step(kLdR30X);
        step(kAndR30R29);
        step(kBrne);
        step(kLdiR24One);
    }
};

/// The one PIN register the pass read (PIND here), with its used bits.
uint8_t used_of_pind(Pass& p) {
    const std::vector<IoBits> u = p.use.finish();
    EXPECT_EQ(u.size(), 1U);
    EXPECT_TRUE(u.empty() || u[0].address == kPind);
    return u.empty() ? 0 : u[0].used;
}

TEST(IoBitUse, DigitalReadUsesTheMaskedBitOnly) {
    Pass p;
    p.digital_read(0x80);
    EXPECT_EQ(used_of_pind(p), 0x80);
}

TEST(IoBitUse, AMaskThatMayDifferFromPassToPassUsesEveryBit) {
    // The mask read from TCNT0: another pass may keep other bits.
    Pass p;
    p.step(kInR29Tcnt0);
    p.data[29] = 0x80;
    p.set_x(kPind);
    p.step(kLdR30X);
    p.step(kAndR30R29);
    EXPECT_EQ(used_of_pind(p), 0xFF);
}

TEST(IoBitUse, SkipOnAnIoBitUsesThatBit) {
    Pass p;
    p.step(kSbisPind7);
    EXPECT_EQ(used_of_pind(p), 0x80);
}

TEST(IoBitUse, AStoredReadUsesEveryBit) {
    Pass p;
    p.step(kInR24Pind);
    p.step(kStsR24, 0x0100);
    p.step(kLdiR24Zero);
    EXPECT_EQ(used_of_pind(p), 0xFF);
}

TEST(IoBitUse, BitsStillHeldWhenThePassEndsAreUsed) {
    Pass p;
    p.step(kInR24Pind);
    p.step(kAndiR24x0C);
    EXPECT_EQ(used_of_pind(p), 0x0C);
}

TEST(IoBitUse, ACopyTestedForOneBitUsesThatBit) {
    Pass p;
    p.step(kInR24Pind);
    p.step(kMovR18R24);
    p.step(kSbrsR18b3);
    p.step(kLdiR18Zero);
    p.step(kLdiR24Zero);
    EXPECT_EQ(used_of_pind(p), 0x08);
}

TEST(IoBitUse, FlagsOfAMaskedValueCarryItsBits) {
    // TST of the masked value, then a branch on Z: the masked bits are used.
    Pass p;
    p.step(kInR24Pind);
    p.step(kAndiR24x0C);
    p.step(kTstR24);
    p.step(kBrne);
    p.step(kLdiR24Zero);
    EXPECT_EQ(used_of_pind(p), 0x0C);
    // Overwritten before anything reads them: nothing used, the register still listed.
    Pass q;
    q.step(kInR24Pind);
    q.step(kLdiR24Zero);
    EXPECT_EQ(used_of_pind(q), 0);
}

TEST(IoBitUse, OtherIoReadsAreNotFollowed) {
    Pass p;
    p.step(kInR29Tcnt0);
    p.step(kLdiR24Zero);
    EXPECT_TRUE(p.use.finish().empty());
}

}  // namespace
}  // namespace ddmr::hil
