// callgrind.out read by valgrind's callgrind_annotate (Debian package
// valgrind): it parses the file, and what it adds up is the profile's.
#include "callgrind_output.hpp"

#include <gtest/gtest.h>

#include <string>

#include "profile_lines.hpp"
#include "support/callgrind_annotate.hpp"
#include "support/profiled_fixture.hpp"

namespace ddmr::test {
namespace {

using hil::Cycles;

TEST(CallgrindOutput, CallgrindAnnotateAddsUpTheControlLoop) {
    const ProfiledFixture f(30'000);
    f.expect_busy();
    const uint64_t n = f.iterations();
    const uint64_t e = f.interrupts();
    const tools::FunctionProfileContext c = f.context();
    EXPECT_EQ(tools::callgrind_scope(f.profiler), "control_loop");
    const std::string text = tools::callgrind_profile(f.profiler, c, f.elf.path().string());
    EXPECT_NE(text.find("\ndesc: Scope: control_loop: " + std::to_string(n) + " completed"), std::string::npos);

    // Self costs: the total is the scope's cycles, 50 n + 21 e.
    const CallgrindAnnotation self = callgrind_annotate(text, false);
    EXPECT_EQ(self.total, f.profiler.control_loop().cycles);
    EXPECT_EQ(self.total, 50 * n + 21 * e);
    EXPECT_EQ(self.functions.at("leaf"), 8 * (2 * n + e));
    EXPECT_EQ(self.functions.at("main"), 14 * n);
    EXPECT_EQ(self.functions.at("__vector_1"), 10 * e);
    EXPECT_EQ(self.functions.at("__vectors"), 3 * e);  // INT0's JMP, line 0 of "???"
    // Inclusive costs from the calls= lines: main's calls are its iterations'
    // (the edge from __init made no call in the loop and is left out).
    const CallgrindAnnotation incl = callgrind_annotate(text, true);
    EXPECT_EQ(incl.functions.at("main"), 50 * n);
    EXPECT_EQ(incl.functions.at("middle"), 18 * n);
    EXPECT_EQ(incl.functions.at("tailer"), 12 * n);
    EXPECT_EQ(incl.functions.at("leaf"), 8 * (2 * n + e));
    EXPECT_EQ(incl.functions.at("__vector_1"), 18 * e);
}

TEST(CallgrindOutput, WithoutLoopIterationsItIsTheWholeRun) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "profile_fixture.elf");
    hil::AvrCore core(elf);
    hil::FunctionProfiler prof(core);
    core.run_until(5'000);
    const tools::FunctionProfileContext c{16'000'000, "mark", {}, {}};  // no lines: all at line 0
    EXPECT_EQ(tools::callgrind_scope(prof), "whole_run");
    const std::string text = tools::callgrind_profile(prof, c, elf.path().string());
    EXPECT_NE(text.find("\ndesc: Scope: whole_run: "), std::string::npos);
    const CallgrindAnnotation self = callgrind_annotate(text, false);
    EXPECT_EQ(self.total, core.cycle());
    // The start-up code: 6 instructions and CALL main, 10 cycles (function_profiler_test).
    EXPECT_EQ(self.functions.at("__init"), 10u);
}

}  // namespace
}  // namespace ddmr::test
