// The 74HC595 part (hil/parts/shift_register_74hc595.cpp) driven by
// tests/firmware/shift_fixture.c as AFMotor drives the shield's: the
// datasheet's function table (Nexperia 74HC595 section 7 Table 3).
#include <gtest/gtest.h>

#include "hil/parts/part_registry.hpp"
#include "hil/parts/part_set.hpp"
#include "support/fixture_core.hpp"

namespace ddmr::test {
namespace {

constexpr hil::Cycles kSendLimit = 20000;  // one byte: 8 clocks of a few cycles each

/// A 74HC595 on D8/D4/D12/D7, named "sr" (from a board file: "8" -> pin 8).
hil::PartEntry shift_register_entry() {
    hil::PartEntry e;
    e.name = "sr";
    e.type = "74hc595";
    e.values["DS"] = {"8", 8, 0};
    e.values["SHCP"] = {"4", 4, 0};
    e.values["STCP"] = {"12", 12, 0};
    e.values["OE"] = {"7", 7, 0};
    e.values["MR"] = {"high", -1, 0};
    return e;
}

struct ShiftRig {
    FixtureCore fx{"shift_fixture"};
    std::vector<hil::PartEntry> entries{shift_register_entry()};
    hil::PartSet parts{fx.core, entries, hil::PartRegistry::global(), [] { return plant::Pose{}; }};
    uint8_t next_request = 1;

    /// Sends `byte` with OE at `oe`; the outputs as a byte.
    uint8_t send(uint8_t byte, bool oe = false) {
        if (fx.core.cycle() < FixtureCore::kPastStartup) fx.core.run_until(FixtureCore::kPastStartup);
        fx.poke("data", byte);
        fx.poke("oe", oe ? 1 : 0);
        EXPECT_TRUE(fx.handshake("request", "done", next_request++, kSendLimit));
        return outputs();
    }
    [[nodiscard]] uint8_t outputs() const {
        uint8_t b = 0;
        for (int i = 0; i < 8; ++i) {
            if (parts.output("sr", "Q" + std::to_string(i)).level_at(fx.core.cycle())) b = static_cast<uint8_t>(b | (1U << i));
        }
        return b;
    }
};

TEST(ShiftRegister74hc595, LatchedBytesAppearOnQ0ToQ7BitForBit) {
    ShiftRig rig;
    EXPECT_EQ(rig.outputs(), 0x00);  // power-on: cleared (undefined on the chip)
    EXPECT_EQ(rig.send(0xA5), 0xA5);
    EXPECT_EQ(rig.send(0x06), 0x06);  // the shield's M1 and M2 FORWARD (bits 2 and 1)
    EXPECT_EQ(rig.send(0x80), 0x80);
    // Q7S is stage 7: the first bit shifted in of the last byte (bit 7 of 0x80).
    EXPECT_TRUE(rig.parts.output("sr", "Q7S").level_at(rig.fx.core.cycle()));
}

TEST(ShiftRegister74hc595, OutputEnableHighMakesTheOutputsHighImpedanceReadAsLow) {
    ShiftRig rig;
    EXPECT_EQ(rig.send(0xFF, /*oe=*/true), 0x00);
    EXPECT_EQ(rig.send(0x3C, /*oe=*/false), 0x3C);
}

TEST(ShiftRegister74hc595, OutputsChangeAtTheLatchEdgeOnlyAndTellTheirListeners) {
    ShiftRig rig;
    std::vector<std::pair<bool, hil::Cycles>> q1_changes;
    rig.parts.output("sr", "Q1").add_listener([&](bool level, hil::Cycles c) { q1_changes.emplace_back(level, c); });
    const uint64_t revision = rig.parts.output("sr", "Q1").revision();
    rig.send(0x02);
    ASSERT_EQ(q1_changes.size(), 1U);  // one change, at the latch: not at the 8 clocks before it
    EXPECT_TRUE(q1_changes[0].first);
    EXPECT_GT(q1_changes[0].second, FixtureCore::kPastStartup);
    EXPECT_EQ(rig.parts.output("sr", "Q1").revision(), revision + 1);
    rig.send(0x02);  // the same byte again: no change
    EXPECT_EQ(q1_changes.size(), 1U);
}

TEST(ShiftRegister74hc595, TruthColumnIsTheOutputByte) {
    ShiftRig rig;
    rig.send(0x5A);
    EXPECT_EQ(rig.parts.truth_columns(), std::vector<std::string>{"sr.Q"});
    std::vector<double> values;
    rig.parts.truth_values(values);
    EXPECT_EQ(values, std::vector<double>{0x5A});
}

}  // namespace
}  // namespace ddmr::test
