// profile.json / profile.txt's call graph and source lines on the
// hand-counted profile fixture (tests/support/profiled_fixture.hpp).
#include "function_profile_output.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "profile_lines.hpp"
#include "support/profiled_fixture.hpp"

namespace ddmr::test {
namespace {

using hil::Cycles;
using nlohmann::json;

const json& edge_row(const json& graph, const std::string& caller, const std::string& callee) {
    const auto it = std::find_if(graph.begin(), graph.end(),
                                 [&](const json& e) { return e["caller"] == caller && e["callee"] == callee; });
    if (it == graph.end()) throw std::runtime_error("no edge " + caller + " -> " + callee);
    return *it;
}

TEST(FunctionProfileOutput, CallGraphHasTheFixturesEdgesByHand) {
    const ProfiledFixture f(30'000);
    f.expect_busy();
    const uint64_t n = f.iterations();
    const uint64_t e = f.interrupts();
    const json p = tools::function_profile_json(f.profiler, f.context());
    const json& graph = p["scopes"]["control_loop"]["call_graph"];
    // Call sites of one caller and callee are one edge: leaf has three callers.
    const auto check = [&](const std::string& caller, const std::string& callee, uint64_t calls, Cycles inclusive) {
        const json& row = edge_row(graph, caller, callee);
        EXPECT_EQ(row["calls"], calls) << caller << " -> " << callee;
        EXPECT_EQ(row["inclusive_cycles"], inclusive) << caller << " -> " << callee;
    };
    check("main", "middle", n, 18 * n);
    check("main", "tailer", n, 12 * n);
    check("main", "mark", n, 6 * n);
    check("middle", "leaf", n, 8 * n);
    check("tailer", "leaf", n, 8 * n);
    check("__vector_1", "leaf", e, 8 * e);
    check("<spontaneous>", "__vector_1", e, 18 * e);
    check("<spontaneous>", "__vectors", 0, 50 * n + 3 * e);
    check("__vectors", "__init", 0, 50 * n);
    check("__init", "main", 0, 50 * n);
    EXPECT_EQ(graph.size(), 10u);
    EXPECT_TRUE(edge_row(graph, "<spontaneous>", "__vectors")["caller_address"].is_null());
    EXPECT_EQ(edge_row(graph, "main", "middle")["callee_address"], 0x8a);
    // By inclusive cycles, largest first.
    for (std::size_t i = 1; i < graph.size(); ++i) {
        EXPECT_GE(graph[i - 1]["inclusive_cycles"].get<Cycles>(), graph[i]["inclusive_cycles"].get<Cycles>());
    }

    // gprof style: leaf's callers above its entry, as calls out of its 2n + e.
    const std::string text = tools::function_profile_text(f.profiler, f.context());
    const std::string leaf_calls = std::to_string(2 * n + e);
    const std::size_t entry = text.find(" " + leaf_calls + "  leaf [");
    ASSERT_NE(entry, std::string::npos) << text;
    const std::string before = text.substr(text.rfind("\n\n", entry), entry - text.rfind("\n\n", entry));
    EXPECT_NE(before.find(std::to_string(n) + "/" + leaf_calls + "      middle ["), std::string::npos) << before;
    EXPECT_NE(before.find(std::to_string(e) + "/" + leaf_calls + "      __vector_1 ["), std::string::npos) << before;
    EXPECT_NE(text.find("Call graph (gprof style)"), std::string::npos);
}

// avr-addr2line -e profile_fixture.elf (its -g stabs) puts the loop's
// instructions on these lines of tests/firmware/profile_fixture.c:
//   20 leaf's NOPs and RET                    8 per call (2n + e calls)
//   25 middle's NOP 1, 26 its CALL 4, 27 its NOP and RET 1 + 4   per iteration
//   32 tailer's NOP 1, 33 its JMP 3
//   37 mark: 6
//   42 __vector_1's NOP, CALL, NOP, RETI: 10 per interrupt
//   50 CALL middle 4, 51 CALL tailer 4, 52 CALL mark and RJMP 4 + 2
// and none on the vector table: __vectors+0x4 (INT0's JMP) is 3 per
// interrupt without line info. The sum is 50 n + 21 e, the scope's cycles.
TEST(FunctionProfileOutput, SourceLinesHaveTheFixturesCyclesByHand) {
    const ProfiledFixture f(30'000);
    const uint64_t n = f.iterations();
    const uint64_t e = f.interrupts();
    const json p = tools::function_profile_json(f.profiler, f.context());
    EXPECT_TRUE(p["line_info"]["error"].is_null());
    const json& sl = p["scopes"]["control_loop"]["source_lines"];
    const auto& lines = sl["lines"];
    const auto cycles_at = [&](int line) -> Cycles {
        for (const json& l : lines) {
            const std::string file = l["file"];
            if (l["line"] == line && file.size() > 17 && file.substr(file.size() - 17) == "profile_fixture.c") {
                return l["self_cycles"].get<Cycles>();
            }
        }
        return 0;
    };
    EXPECT_EQ(cycles_at(20), 8 * (2 * n + e));
    EXPECT_EQ(cycles_at(25), n);
    EXPECT_EQ(cycles_at(26), 4 * n);
    EXPECT_EQ(cycles_at(27), 5 * n);
    EXPECT_EQ(cycles_at(32), n);
    EXPECT_EQ(cycles_at(33), 3 * n);
    EXPECT_EQ(cycles_at(37), 6 * n);
    EXPECT_EQ(cycles_at(42), 10 * e);
    EXPECT_EQ(cycles_at(50), 4 * n);
    EXPECT_EQ(cycles_at(51), 4 * n);
    EXPECT_EQ(cycles_at(52), 6 * n);
    EXPECT_EQ(lines.size(), 11u);
    EXPECT_EQ(lines[0]["line"], 20);  // the most cycles first
    EXPECT_EQ(lines[0]["functions"], json::array({"leaf"}));
    EXPECT_EQ(sl["line_cycles"], 50 * n + 18 * e);
    // Said, not dropped: INT0's vector JMP.
    ASSERT_EQ(sl["no_line_info"].size(), 1u);
    EXPECT_EQ(sl["no_line_info"][0]["label"], "(no line info) __vectors+0x4");
    EXPECT_EQ(sl["no_line_info"][0]["self_cycles"], 3 * e);
    EXPECT_EQ(sl["no_line_info_cycles"], 3 * e);
    EXPECT_DOUBLE_EQ(sl["no_line_info_share"].get<double>(),
                     static_cast<double>(3 * e) / static_cast<double>(50 * n + 21 * e));
    // The whole run adds the start-up code, which has no line either.
    const json& whole = p["scopes"]["whole_run"]["source_lines"];
    EXPECT_EQ(whole["line_cycles"].get<Cycles>() + whole["no_line_info_cycles"].get<Cycles>(),
              p["scopes"]["whole_run"]["cycles"].get<Cycles>());
    const auto& unlined = whole["no_line_info"];
    EXPECT_NE(std::find_if(unlined.begin(), unlined.end(),
                           [](const json& u) { return u["label"] == "(no line info) __init+0x0"; }),
              unlined.end());

    const std::string text = tools::function_profile_text(f.profiler, f.context());
    EXPECT_NE(text.find("profile_fixture.c:20 (leaf)"), std::string::npos) << text;
    EXPECT_NE(text.find("(no line info) __vectors+0x4"), std::string::npos) << text;
}

TEST(FunctionProfileOutput, AnElfWithoutLinesHasEveryCycleWithoutLineInfo) {
    // loop_fixture.elf is built without -g: nothing is dropped, all is "no line info".
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "loop_fixture.elf");
    hil::AvrCore core(elf);
    hil::FunctionProfiler prof(core);
    core.run_until(5'000);
    const tools::AddressLines lines = tools::profile_lines(elf.path(), prof);
    EXPECT_TRUE(lines.empty());
    const tools::ScopeLines sl = tools::scope_lines(prof.whole_run(), prof.map(), lines);
    EXPECT_TRUE(sl.lines.empty());
    EXPECT_EQ(sl.unlined_cycles, core.cycle());
}

}  // namespace
}  // namespace ddmr::test
