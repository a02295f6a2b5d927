// TwiSlave: a register device at 0x68 on the I2C bus, driven by an I2C
// master written from the ATmega328P datasheet's TWI section
// (tests/firmware/twi_fixture.c; status codes of Tables 22-3 and 22-4).
#include "hil/twi_slave.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "support/fixture_core.hpp"

namespace ddmr::test {
namespace {

constexpr int kDevice = 0x68;

struct TwiRig {
    FixtureCore f{"twi_fixture"};
    hil::TwiSlave slave{f.core, kDevice};
    std::vector<std::pair<uint8_t, uint8_t>> writes;
    TwiRig() {
        const uint8_t block[6] = {0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC};  // 0x3B..0x40
        for (uint8_t i = 0; i < 6; ++i) slave.set_reg(static_cast<uint8_t>(0x3B + i), block[i]);
        slave.set_write_listener([this](uint8_t reg, uint8_t value) { writes.emplace_back(reg, value); });
        // 4 transactions of a few bytes at about 9 us a byte: well within 50 ms.
        EXPECT_TRUE(f.run_until_u8("done", 1, hil::ms_to_cycles(50, f.core.clock_hz())));
    }
};

TEST(TwiSlave, WritesSetThePointerThenStoreWithAutoIncrement) {
    TwiRig r;
    EXPECT_EQ(r.slave.reg(0x10), 0xA5);
    EXPECT_EQ(r.slave.reg(0x11), 0x5A);
    ASSERT_EQ(r.writes.size(), 2u);  // the pointer byte is not a register write
    EXPECT_EQ(r.writes[0], (std::pair<uint8_t, uint8_t>{0x10, 0xA5}));
    EXPECT_EQ(r.writes[1], (std::pair<uint8_t, uint8_t>{0x11, 0x5A}));
    // Master transmitter (Table 22-3): START 0x08, SLA+W ACK 0x18, data ACK 0x28.
    const std::vector<uint8_t> first = r.f.bytes("status", 5);
    EXPECT_EQ(first, (std::vector<uint8_t>{0x08, 0x18, 0x28, 0x28, 0x28}));
}

TEST(TwiSlave, ReadsSixBytesFromARegisterBlock) {
    TwiRig r;
    EXPECT_EQ(r.f.bytes("block", 6), (std::vector<uint8_t>{0x12, 0x34, 0x56, 0x78, 0x9A, 0xBC}));
    // Then: START, SLA+W, pointer, repeated START 0x10, SLA+R ACK 0x40,
    // 5 bytes ACKed 0x50, the last NACKed 0x58 (Table 22-4).
    const std::vector<uint8_t> s = r.f.bytes("status", 16);
    EXPECT_EQ(std::vector<uint8_t>(s.begin() + 5, s.begin() + 16),
              (std::vector<uint8_t>{0x08, 0x18, 0x28, 0x10, 0x40, 0x50, 0x50, 0x50, 0x50, 0x50, 0x58}));
}

TEST(TwiSlave, ThePointerSurvivesAStop) {
    TwiRig r;
    // Pointer 0x10 written, STOP, then a read: 0x10 and 0x11 as written.
    EXPECT_EQ(r.f.bytes("readback", 2), (std::vector<uint8_t>{0xA5, 0x5A}));
    EXPECT_EQ(r.slave.pointer(), 0x12);
    EXPECT_EQ(r.slave.stats().transactions, 5u);  // write; write + Sr read; write, STOP, read
    EXPECT_EQ(r.slave.stats().bytes_read, 8u);
    EXPECT_EQ(r.slave.stats().bytes_written, 5u);
}

TEST(TwiSlave, AnotherAddressIsNotAcknowledged) {
    TwiRig r;
    EXPECT_EQ(r.f.u8("nack_w"), 0x20);  // SLA+W sent, NOT ACK received
    EXPECT_EQ(r.f.u8("nack_r"), 0x48);  // SLA+R sent, NOT ACK received
}

TEST(TwiSlave, RefusesAReservedAddress) {
    FixtureCore f{"twi_fixture"};
    expect_invalid_argument([&] { hil::TwiSlave slave(f.core, 0x78); }, "address 0x78");
}

TEST(TwiSlave, EachByteTakesNineSclPeriodsOfTheBusTwbrSets) {
    // 100 kHz (TWBR = 72, prescaler 1): an SCL period is 16 + 2 x 72 = 160
    // cycles, a byte and its ACK 9 x 160 = 1440 (datasheet 22.5.2). The
    // fixture's 6-byte burst starts each byte (a TWCR write, when the slave
    // is asked for it) as soon as TWINT shows the previous one done: the
    // bytes are 1440 cycles apart plus the master's instructions between
    // them (its status bookkeeping, the store, the loop: 44-45 cycles
    // measured); simavr 1.6 alone: 9 us = 144 cycles.
    FixtureCore f{"twi_fixture"};
    hil::TwiSlave slave{f.core, kDevice};
    std::vector<hil::Cycles> read_at;
    slave.set_read_listener([&](uint8_t /*reg*/) { read_at.push_back(f.core.cycle()); });
    ASSERT_TRUE(f.run_until_u8("done", 1, hil::ms_to_cycles(50, f.core.clock_hz())));
    ASSERT_GE(read_at.size(), 6U);  // the burst of 6, then the 2 read back
    for (std::size_t i = 1; i < 6; ++i) {
        const hil::Cycles gap = read_at[i] - read_at[i - 1];
        EXPECT_GE(gap, 1440U) << i;
        EXPECT_LE(gap, 1440U + 60U) << i;
    }
}

}  // namespace
}  // namespace ddmr::test
