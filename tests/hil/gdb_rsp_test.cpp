// The remote protocol's pure pieces: checksums and escapes worked out by hand,
// the reader's events, avr-gdb's 39-byte register packet from a known state,
// and the address spaces avr-gdb uses.
#include "hil/gdb_rsp.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

namespace ddmr::test {
namespace {

using namespace hil::rsp;

std::vector<Event> feed_all(PacketReader& reader, const std::string& bytes) {
    std::vector<Event> events;
    for (char c : bytes) {
        if (auto e = reader.feed(c)) events.push_back(*e);
    }
    return events;
}

TEST(GdbRsp, ChecksumIsTheByteSumModulo256) {
    // 'O' 0x4f + 'K' 0x4b = 0x9a.
    EXPECT_EQ(checksum("OK"), 0x9a);
    EXPECT_EQ(frame("OK"), "$OK#9a");
    EXPECT_EQ(frame(""), "$#00");
    // 'm' 0x6d + '0' 0x30 + ',' 0x2c + '4' 0x34 = 0xfd.
    EXPECT_EQ(frame("m0,4"), "$m0,4#fd");
    // 300 bytes of 0xff: 300 * 255 = 76500 = 0x12ad4 -> 0xd4.
    EXPECT_EQ(checksum(std::string(300, '\xff')), 0xd4);
}

TEST(GdbRsp, FrameEscapesTheFourSpecialBytes) {
    // '$' 0x24 -> "}\x04", '#' 0x23 -> "}\x03", '}' 0x7d -> "}]", '*' 0x2a -> "}\x0a";
    // the checksum covers the escaped body.
    const std::string body = std::string("a}\x04") + "}\x03" + "}]" + "}\x0a";
    const std::string framed = frame("a$#}*");
    EXPECT_EQ(framed.substr(0, framed.size() - 3), "$" + body);
    char cs[3];
    std::snprintf(cs, sizeof cs, "%02x", checksum(body));
    EXPECT_EQ(framed.substr(framed.size() - 2), cs);
    EXPECT_EQ(unescape(body), "a$#}*");
}

TEST(GdbRsp, ReaderReturnsPacketsAcksAndInterrupts) {
    PacketReader reader;
    const auto events = feed_all(reader, std::string("+$m0,4#fd-\x03garbage$?#3f"));
    ASSERT_EQ(events.size(), 5u);
    EXPECT_EQ(events[0].kind, Event::Kind::kAck);
    EXPECT_EQ(events[1].kind, Event::Kind::kPacket);
    EXPECT_EQ(events[1].payload, "m0,4");
    EXPECT_EQ(events[2].kind, Event::Kind::kNak);
    EXPECT_EQ(events[3].kind, Event::Kind::kInterrupt);
    EXPECT_EQ(events[4].kind, Event::Kind::kPacket);
    EXPECT_EQ(events[4].payload, "?");
}

TEST(GdbRsp, ReaderRejectsABadChecksumAndRecovers) {
    PacketReader reader;
    auto events = feed_all(reader, "$m0,4#fe$m0,4#zz$m0,4#fd");
    ASSERT_EQ(events.size(), 3u);
    EXPECT_EQ(events[0].kind, Event::Kind::kBadChecksum);
    EXPECT_EQ(events[1].kind, Event::Kind::kBadChecksum);
    EXPECT_EQ(events[2].kind, Event::Kind::kPacket);
    EXPECT_EQ(events[2].payload, "m0,4");
}

TEST(GdbRsp, ReaderUndoesFrameForEveryByteValue) {
    std::string all;
    for (int b = 0; b < 256; ++b) all.push_back(static_cast<char>(b));
    PacketReader reader;
    const auto events = feed_all(reader, frame("X800100,100:" + all));
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].kind, Event::Kind::kPacket);
    EXPECT_EQ(events[0].payload, "X800100,100:" + all);
}

TEST(GdbRsp, HexEncodesAndDecodes) {
    EXPECT_EQ(to_hex(std::vector<uint8_t>{0x00, 0x0a, 0xff}), "000aff");
    EXPECT_EQ(from_hex("0aFF"), (std::vector<uint8_t>{0x0a, 0xff}));
    EXPECT_FALSE(from_hex("abc").has_value());
    EXPECT_FALSE(from_hex("zz").has_value());
    EXPECT_EQ(parse_hex_number("810010"), 0x810010u);
    EXPECT_FALSE(parse_hex_number("").has_value());
    EXPECT_FALSE(parse_hex_number("12g").has_value());
    EXPECT_FALSE(parse_hex_number("11112222333344445").has_value());  // 65 bits
}

/// r[i] = i, SREG = 0x82 (I and Z), SP = 0x08FF (RAMEND), PC = 0x012C.
AvrRegisters known_registers() {
    AvrRegisters regs;
    for (std::size_t i = 0; i < regs.r.size(); ++i) regs.r[i] = static_cast<uint8_t>(i);
    regs.sreg = 0x82;
    regs.sp = 0x08FF;
    regs.pc = 0x012C;
    return regs;
}

TEST(GdbRsp, RegisterPacketIsAvrGdbsLayout) {
    const std::string g = encode_registers(known_registers());
    ASSERT_EQ(g.size(), 2 * kRegisterPacketBytes);  // 39 bytes
    EXPECT_EQ(g.substr(0, 8), "00010203");
    EXPECT_EQ(g.substr(62, 2), "1f");        // r31
    EXPECT_EQ(g.substr(64, 2), "82");        // SREG, reg 32
    EXPECT_EQ(g.substr(66, 4), "ff08");      // SP, reg 33, little-endian
    EXPECT_EQ(g.substr(70, 8), "2c010000");  // PC, reg 34, 4 bytes little-endian
    AvrRegisters back;
    ASSERT_TRUE(decode_registers(g, back));
    EXPECT_EQ(back.r, known_registers().r);
    EXPECT_EQ(back.sreg, 0x82);
    EXPECT_EQ(back.sp, 0x08FF);
    EXPECT_EQ(back.pc, 0x012Cu);
    EXPECT_FALSE(decode_registers(g.substr(2), back));
}

TEST(GdbRsp, SingleRegistersAndTheStopReply) {
    AvrRegisters regs = known_registers();
    EXPECT_EQ(register_size(0), 1u);
    EXPECT_EQ(register_size(kRegSreg), 1u);
    EXPECT_EQ(register_size(kRegSp), 2u);
    EXPECT_EQ(register_size(kRegPc), 4u);
    EXPECT_EQ(register_size(35), 0u);
    EXPECT_EQ(encode_register(regs, 24), "18");
    EXPECT_EQ(encode_register(regs, kRegPc), "2c010000");
    EXPECT_EQ(encode_register(regs, 35), "");
    ASSERT_TRUE(decode_register(kRegSp, "fe07", regs));
    EXPECT_EQ(regs.sp, 0x07FE);
    EXPECT_FALSE(decode_register(kRegSp, "fe", regs));  // SP is two bytes
    EXPECT_FALSE(decode_register(35, "00", regs));
    EXPECT_EQ(stop_reply(kSigTrap, known_registers()), "T0520:82;21:ff08;22:2c010000;");
    EXPECT_EQ(stop_reply(kSigInt, known_registers()).substr(0, 3), "T02");
}

TEST(GdbRsp, AddressSpacesAreAvrGdbs) {
    struct Case {
        uint64_t gdb_address;
        Space space;
        uint32_t offset;
    };
    for (const Case& c : {Case{0x12C, Space::kFlash, 0x12C}, Case{0x7FFFFF, Space::kFlash, 0x7FFFFF},
                          Case{0x8001D1, Space::kData, 0x1D1},  // the reference sketch's Count1
                          Case{0x810010, Space::kEeprom, 0x10}}) {
        const auto a = decode_address(c.gdb_address);
        ASSERT_TRUE(a) << std::hex << c.gdb_address;
        EXPECT_EQ(a->space, c.space) << std::hex << c.gdb_address;
        EXPECT_EQ(a->offset, c.offset) << std::hex << c.gdb_address;
    }
    EXPECT_FALSE(decode_address(0x820000).has_value());  // fuses: not served
}

TEST(GdbRsp, ParsesMemoryRangesAndBreakpoints) {
    const auto m = parse_memory_range("8001d1,4");
    ASSERT_TRUE(m);
    EXPECT_EQ(m->address, 0x8001D1u);
    EXPECT_EQ(m->length, 4u);
    EXPECT_FALSE(parse_memory_range("8001d1").has_value());
    EXPECT_FALSE(parse_memory_range("x,4").has_value());
    const auto z = parse_breakpoint("0,12c,2");
    ASSERT_TRUE(z);
    EXPECT_EQ(z->type, 0u);
    EXPECT_EQ(z->address, 0x12Cu);
    EXPECT_EQ(z->kind, 2u);
    const auto cond = parse_breakpoint("1,12c,2;X2,0a");
    ASSERT_TRUE(cond);
    EXPECT_EQ(cond->kind, 2u);
    EXPECT_FALSE(parse_breakpoint("5,12c,2").has_value());
    EXPECT_FALSE(parse_breakpoint("0,12c").has_value());
}

}  // namespace
}  // namespace ddmr::test
