// A part type registered from this file alone (no other file of the project
// touched) and wired in a board file: the proof that a part is one file.
// Also: the registry's refusals, and parts feeding each other.
#include "hil/parts/part_registry.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "hil/board.hpp"
#include "hil/parts/part_set.hpp"
#include "support/fixture_core.hpp"
#include "support/part_truth.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

/// A test part: counts the rising edges on IN; its output HALF toggles at
/// each of them (a divide-by-two flip-flop), for another part to read.
class EdgeCounter final : public hil::Part {
public:
    explicit EdgeCounter(const hil::PartContext& ctx) : half_(ctx.name() + ".HALF") {
        ctx.input("IN").add_listener([this](bool level, hil::Cycles cycle) {
            if (!level) return;
            ++count_;
            half_.set(!half_.level(), cycle);
        });
    }
    const hil::LogicSignal& output(const std::string& /*port*/) const override { return half_; }
    std::vector<std::string> truth_columns() const override { return {"count"}; }
    void truth_values(std::vector<double>& out) const override { out.push_back(static_cast<double>(count_)); }

private:
    hil::DrivenSignal half_;
    uint64_t count_ = 0;
};

hil::PartType edge_counter_type() {
    hil::PartType t;
    t.type = "test-edge-counter";
    t.summary = "counts rising edges (a test part)";
    t.datasheet = "none: a test";
    t.keys = {hil::PartKey::input("IN", "the signal whose rising edges are counted")};
    t.ports = {{"HALF", "toggles at each rising edge of IN"}};
    t.create = [](const hil::PartContext& ctx) { return std::make_unique<EdgeCounter>(ctx); };
    return t;
}

/// Registers the test part once per process.
void register_test_part() {
    static const bool done = [] {
        hil::PartRegistry::global().add(edge_counter_type());
        return true;
    }();
    (void)done;
}

TEST(PartRegistry, APartTypeRegisteredFromOneFileIsWiredByABoardFile) {
    register_test_part();
    TempDir dir;
    // The 74HC595's clock (D4) feeds one counter; the counter's HALF feeds a
    // second: parts feed each other, listed in any order.
    std::ofstream(dir / "b.yaml") << "board: uno\n"
                                     "parts:\n"
                                     "  - {name: eighth, type: test-edge-counter, IN: clocks.HALF}\n"
                                     "  - {name: clocks, type: test-edge-counter, IN: 4}\n"
                                     "  - {name: sr, type: 74hc595, DS: 8, SHCP: 4, STCP: 12, OE: 7}\n"
                                     "wheels:\n"
                                     "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 13}, encoder: {type: single, OUT: 2}}\n"
                                     "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 9}, encoder: {type: single, OUT: 3}}\n";
    const hil::BoardWiring board = hil::load_board_file(dir / "b.yaml");
    ASSERT_EQ(board.parts.size(), 3U);
    FixtureCore fx{"shift_fixture"};
    const hil::PartSet parts(fx.core, board.parts, hil::PartRegistry::global(), [] { return plant::Pose{}; });
    for (uint8_t r = 1; r <= 3; ++r) {
        fx.poke("data", 0x0F);
        ASSERT_TRUE(fx.handshake("request", "done", r, 20000));
    }
    EXPECT_EQ(truth_value(parts, "clocks.count"), 24);  // 8 clocks per byte
    EXPECT_EQ(truth_value(parts, "eighth.count"), 12);  // every other one
    EXPECT_EQ(truth_value(parts, "sr.Q"), 0x0F);
}

TEST(PartRegistry, RefusesATakenWordAPartWithoutFactoryAndARepeatedKey) {
    register_test_part();
    hil::PartRegistry& r = hil::PartRegistry::global();
    EXPECT_THROW(r.add(edge_counter_type()), std::invalid_argument);
    hil::PartType none = edge_counter_type();
    none.type = "test-no-factory";
    none.create = nullptr;
    EXPECT_THROW(r.add(none), std::invalid_argument);
    hil::PartType twice = edge_counter_type();
    twice.type = "test-twice";
    twice.keys.push_back(hil::PartKey::input("IN", "again"));
    EXPECT_THROW(r.add(twice), std::invalid_argument);
    EXPECT_EQ(r.find("test-twice"), nullptr);
    EXPECT_NE(r.find("74hc595"), nullptr);
}

}  // namespace
}  // namespace ddmr::test
