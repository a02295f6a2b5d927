// VcdWriter: the header GTKWave reads, identifier codes, time conversion,
// ordering of out-of-order events, rejection of late events, windows and
// byte-identical output.
#include "hil/vcd_writer.hpp"

#include <gtest/gtest.h>

#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include "support/vcd_reader.hpp"

namespace ddmr::hil {
namespace {

using test::parse_vcd;

struct Captured {
    std::string text;
    VcdSink sink() {
        return [this](std::string_view s) { text.append(s); };
    }
};

VcdConfig config_16mhz(const char* top = "top") {
    VcdConfig c;
    c.clock_hz = 16'000'000;
    c.top_scope = top;
    return c;
}

/// The dump of one wire "top.a.s" with `initial` and `changes` (cycle, level)
/// reported in order, finished at `end`.
std::string one_wire_dump(bool initial, std::initializer_list<std::pair<Cycles, bool>> changes, Cycles end) {
    Captured out;
    VcdWriter w(out.sink(), config_16mhz());
    const auto s = w.add_wire("a", "s", initial);
    for (const auto& [cycle, level] : changes) w.change(s, cycle, level ? 1 : 0);
    w.finish(end);
    return out.text;
}

TEST(VcdWriter, HeaderDeclaresScopesVarsAndInitialValues) {
    Captured out;
    VcdWriter w(out.sink(), config_16mhz());
    const auto a = w.add_wire("uno", "D2", true);
    const auto b = w.add_vector("fw", "n", 8, 5);
    w.add_comment("hello");
    w.change(a, 16, 0);
    w.change(b, 8, 6);
    w.flush(100);
    w.finish(160);
    // Cycles at 16 MHz: 8 -> 500 ns, 16 -> 1000 ns, 160 -> 10000 ns (62.5 ns per cycle).
    EXPECT_EQ(out.text,
              "$comment\n  hello\n$end\n"
              "$timescale 1ns $end\n"
              "$scope module top $end\n"
              "$scope module uno $end\n$var wire 1 ! D2 $end\n$upscope $end\n"
              "$scope module fw $end\n$var wire 8 \" n [7:0] $end\n$upscope $end\n"
              "$upscope $end\n$enddefinitions $end\n"
              "#0\n$dumpvars\n1!\nb101 \"\n$end\n"
              "#500\nb110 \"\n"
              "#1000\n0!\n"
              "#10000\n");
    const auto f = parse_vcd(out.text);
    EXPECT_EQ(f.timescale, "1ns");
    EXPECT_EQ(f.var("top.fw.n").width, 8u);
    EXPECT_EQ(f.end_time, 10000u);
}

TEST(VcdWriter, IdentifierCodesArePrintableAndUnique) {
    EXPECT_EQ(VcdWriter::identifier(0), "!");
    EXPECT_EQ(VcdWriter::identifier(1), "\"");
    EXPECT_EQ(VcdWriter::identifier(93), "~");
    EXPECT_EQ(VcdWriter::identifier(94), "!!");   // first two-character code
    EXPECT_EQ(VcdWriter::identifier(95), "\"!");
    EXPECT_EQ(VcdWriter::identifier(94 + 94 * 94 - 1), "~~");
    EXPECT_EQ(VcdWriter::identifier(94 + 94 * 94), "!!!");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < 20'000; ++i) {
        const std::string id = VcdWriter::identifier(i);
        for (char c : id) ASSERT_TRUE(c >= '!' && c <= '~') << i;
        ASSERT_TRUE(seen.insert(id).second) << "duplicate code for " << i;
    }
}

TEST(VcdWriter, TimescaleConversionOfKnownCycles) {
    // t_ns = floor(cycle x 1e9 / f): at 16 MHz cycle x 125 / 2.
    EXPECT_EQ(VcdWriter::cycles_to_ns(0, 16'000'000), 0u);
    EXPECT_EQ(VcdWriter::cycles_to_ns(3, 16'000'000), 187u);  // 187.5 rounded down
    EXPECT_EQ(VcdWriter::cycles_to_ns(32'640, 16'000'000), 2'040'000u);  // one PWM period, 2.04 ms
    EXPECT_EQ(VcdWriter::cycles_to_ns(16'000'000, 16'000'000), 1'000'000'000u);
    // Far beyond cycle x 1e9 fitting in 64 bits: 10^12 cycles = 62,500 s.
    EXPECT_EQ(VcdWriter::cycles_to_ns(1'000'000'000'000ull, 16'000'000), 62'500'000'000'000ull);
    EXPECT_EQ(VcdWriter::cycles_to_ns(7, 3), 2'333'333'333u);
    const std::string text = one_wire_dump(false, {{3, true}}, 3);
    EXPECT_NE(text.find("#187\n1!\n"), std::string::npos) << text;
}

TEST(VcdWriter, OutOfOrderEventsAreWrittenByTimeThenDeclaration) {
    Captured out;
    VcdWriter w(out.sink(), config_16mhz());
    const auto first = w.add_wire("a", "first", false);
    const auto second = w.add_wire("a", "second", false);
    w.change(first, 300, 1);
    w.change(second, 100, 1);
    w.change(second, 200, 0);
    w.change(first, 100, 1);  // same cycle as second's: declaration order wins
    w.change(second, 250, 1);
    w.flush(260);             // 300 stays buffered
    EXPECT_EQ(w.buffered(), 1u);
    w.change(first, 270, 0);  // after the flushed horizon: accepted
    w.finish(400);
    const std::string body = out.text.substr(out.text.find("$end\n#6250"));
    // 100 -> 6250 ns, 200 -> 12500, 250 -> 15625, 270 -> 16875, 300 -> 18750.
    EXPECT_EQ(body, "$end\n#6250\n1!\n1\"\n#12500\n0\"\n#15625\n1\"\n#16875\n0!\n#18750\n1!\n#25000\n")
        << out.text;
    const auto f = parse_vcd(out.text);
    EXPECT_EQ(test::edge_count(f.var("top.a.first")), 3u);
}

TEST(VcdWriter, SameCycleChangesOfOneSignalKeepArrivalOrder) {
    // A zero-width pulse at cycle 10: every change written, in order.
    const std::string text = one_wire_dump(false, {{10, true}, {10, false}, {10, true}}, 20);
    EXPECT_NE(text.find("#625\n1!\n0!\n1!\n"), std::string::npos) << text;
}

TEST(VcdWriter, RepeatedValuesAreNotWritten) {
    // Already 1 at cycle 10; 0 twice from cycle 20.
    const auto f = parse_vcd(one_wire_dump(true, {{10, true}, {20, false}, {30, false}}, 40));
    ASSERT_EQ(f.var("top.a.s").changes.size(), 2u);  // $dumpvars 1, then 0 at cycle 20
    EXPECT_EQ(f.var("top.a.s").changes[1].time, 1250u);
}

TEST(VcdWriter, RejectsEventsBeforeTheFlushedHorizon) {
    VcdWriter w(nullptr, config_16mhz());
    const auto s = w.add_wire("a", "s", false);
    w.change(s, 500, 1);
    w.flush(1000);
    EXPECT_THROW(w.change(s, 999, 0), std::logic_error);
    EXPECT_NO_THROW(w.change(s, 1000, 0));
    EXPECT_THROW(w.add_wire("a", "late", false), std::logic_error);
    EXPECT_THROW(w.change(s + 1, 2000, 0), std::logic_error);
    w.finish(2000);
    EXPECT_THROW(w.change(s, 3000, 1), std::logic_error);
}

TEST(VcdWriter, RejectsBadDeclarations) {
    VcdWriter w(nullptr, config_16mhz());
    EXPECT_THROW(w.add_wire("a", "has blank", false), std::invalid_argument);
    EXPECT_THROW(w.add_wire("", "x", false), std::invalid_argument);
    EXPECT_THROW(w.add_vector("a", "wide", 65, 0), std::invalid_argument);
    w.add_wire("a", "x", false);
    EXPECT_THROW(w.add_wire("a", "x", true), std::invalid_argument);
    VcdConfig zero = config_16mhz();
    zero.clock_hz = 0;
    EXPECT_THROW(VcdWriter(nullptr, zero), std::invalid_argument);
    VcdConfig backwards = config_16mhz();
    backwards.window.begin_cycle = 10;
    backwards.window.end_cycle = 5;
    EXPECT_THROW(VcdWriter(nullptr, backwards), std::invalid_argument);
}

std::string scripted_dump(VcdConfig config) {
    Captured out;
    VcdWriter w(out.sink(), config);
    const auto clk = w.add_wire("a", "clk", false);
    const auto n = w.add_vector("a", "n", 32, 0);
    for (Cycles c = 0; c < 10'000; c += 7) {
        w.change(clk, c + 3, (c / 7) % 2);
        w.change(n, c, c / 7);
        if (c % 700 == 0) w.flush(c > 50 ? c - 50 : 0);
    }
    w.finish(10'000);
    return out.text;
}

TEST(VcdWriter, SameEventsGiveByteIdenticalOutput) {
    const std::string a = scripted_dump(config_16mhz());
    const std::string b = scripted_dump(config_16mhz());
    EXPECT_GT(a.size(), 10'000u);
    EXPECT_EQ(a, b);
    EXPECT_EQ(a.find("$date"), std::string::npos);  // nothing from the wall clock
}

TEST(VcdWriter, WindowStartsWithTheValuesAtItsBeginAndDropsLaterEvents) {
    VcdConfig c = config_16mhz();
    c.window.begin_cycle = 1000;
    c.window.end_cycle = 2000;
    Captured out;
    VcdWriter w(out.sink(), c);
    const auto s = w.add_wire("a", "s", false);
    const auto n = w.add_vector("a", "n", 16, 0);
    w.change(n, 10, 7);      // before the window: becomes the initial value
    w.change(s, 500, 1);
    w.change(s, 1500, 0);    // inside
    w.change(n, 2500, 9);    // after: dropped
    w.flush(3000);
    w.finish(4000);
    const auto f = parse_vcd(out.text);
    EXPECT_EQ(f.timestamps.front(), 62'500u);  // cycle 1000
    EXPECT_EQ(f.end_time, 125'000u);           // the window's end, cycle 2000
    ASSERT_EQ(f.var("top.a.n").changes.size(), 1u);
    EXPECT_EQ(f.var("top.a.n").changes[0].value, 7u);
    ASSERT_EQ(f.var("top.a.s").changes.size(), 2u);
    EXPECT_EQ(f.var("top.a.s").changes[0].value, 1u);
    EXPECT_EQ(f.var("top.a.s").changes[1].time, 93'750u);  // cycle 1500
}

TEST(VcdWriter, LastCyclesWindowKeepsOnlyTheTailBeforeFinish) {
    VcdConfig c = config_16mhz();
    c.window.last_cycles = 100;
    Captured out;
    VcdWriter w(out.sink(), c);
    const auto n = w.add_vector("a", "n", 32, 0);
    for (Cycles cycle = 10; cycle <= 1000; cycle += 10) {
        w.change(n, cycle, cycle / 10);
        w.flush(cycle);
    }
    EXPECT_TRUE(out.text.empty());  // written only by finish
    EXPECT_LE(w.buffered(), 12u);   // memory bounded by the window
    w.finish(1005);
    const auto f = parse_vcd(out.text);
    // Window [905, 1005]: value 90 (set at 900) first, then 91..100.
    const auto& ch = f.var("top.a.n").changes;
    ASSERT_EQ(ch.size(), 11u);
    EXPECT_EQ(ch.front().time, VcdWriter::cycles_to_ns(905, 16'000'000));
    EXPECT_EQ(ch.front().value, 90u);
    EXPECT_EQ(ch.back().value, 100u);
    EXPECT_EQ(f.end_time, VcdWriter::cycles_to_ns(1005, 16'000'000));
}

}  // namespace
}  // namespace ddmr::hil
