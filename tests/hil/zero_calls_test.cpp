// The scan of a firmware ELF for calls and jumps to address 0 (issue 32):
// a weak call nothing defines links to `call 0`, a restart. Reported only
// where nothing guards it; the reference firmware and the examples built
// here (their serialEventRun tests the weak serialEvent, their
// __bad_interrupt jumps to 0) have none.
#include "hil/zero_calls.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "hil/avr_decode.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

hil::ZeroCallReport scan(const std::string& elf_name) {
    return hil::find_zero_calls(hil::ElfImage::read(test_firmware_dir() / elf_name));
}

TEST(ZeroCalls, AWeakCallTheCodeTestsFirstIsNotReported) {
    // main: ldi r24, 0; ldi r25, 0; or r24, r25; breq past; call 0.
    const auto report = scan("weak_call_fixture_guarded.elf");
    EXPECT_TRUE(report.calls.empty()) << hil::describe_zero_calls(report).front();
    EXPECT_EQ(report.unresolved_weak, std::vector<std::string>{"hook"});
}

TEST(ZeroCalls, AnUnguardedWeakCallIsReportedInItsFunction) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "weak_call_fixture_unguarded.elf");
    const auto report = hil::find_zero_calls(elf);
    ASSERT_EQ(report.calls.size(), 1U);
    EXPECT_EQ(report.calls[0].pc, elf.require("main").address);  // main's first instruction
    EXPECT_EQ(report.calls[0].instruction, "call");
    EXPECT_EQ(report.calls[0].function, "main");
    const auto lines = hil::describe_zero_calls(report);
    ASSERT_EQ(lines.size(), 1U);
    EXPECT_EQ(lines[0], "`call 0` at 0x0090 in main: an unguarded call to address 0 restarts the firmware (the ELF's "
                        "unresolved weak symbol hook is the likely callee: nothing defines it)");
}

TEST(ZeroCalls, NewWithTheCoresWeakDeclarationNamesItsFunctionAndOperatorNew) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "new_without_core.elf");
    const auto report = hil::find_zero_calls(elf);
    // Only watch()'s `new`: not serialEventRun's tested `jmp 0`, not __bad_interrupt's.
    ASSERT_EQ(report.calls.size(), 1U);
    EXPECT_EQ(report.calls[0].function, "watch(unsigned char)");
    const auto watch = elf.require("_Z5watchh");
    EXPECT_GE(report.calls[0].pc, watch.address);
    EXPECT_LT(report.calls[0].pc, watch.address + watch.size);
    // serialEvent is weak and undefined too: the linked ELF cannot say which one each call meant.
    EXPECT_EQ(report.unresolved_weak, (std::vector<std::string>{"operator new(unsigned int)", "serialEvent()"}));
    const std::string line = hil::describe_zero_calls(report).at(0);
    EXPECT_NE(line.find("in watch(unsigned char): an unguarded call to address 0 restarts the firmware"),
              std::string::npos)
        << line;
    EXPECT_NE(line.find("one of the ELF's unresolved weak symbols, which nothing defines: operator new(unsigned "
                        "int), serialEvent()"),
              std::string::npos)
        << line;
}

TEST(ZeroCalls, TheReferenceFirmwareAndTheBuiltExamplesHaveNone) {
    for (const auto& elf : {firmware_elf(), test_firmware_dir() / "pro_mini_8mhz_tb6612.elf",
                            test_firmware_dir() / "mega_l298n_int45.elf", test_firmware_dir() / "library_odometry.elf"}) {
        const auto image = hil::ElfImage::read(elf);
        const auto report = hil::find_zero_calls(image);
        EXPECT_TRUE(report.calls.empty()) << elf << ": " << hil::describe_zero_calls(report).front();
        // What the scan passes over is there: __bad_interrupt's jump to 0, and
        // calls of weak symbols nothing defines (the core's serialEvent*, and
        // on the Mega Serial1_available() ... for its unused ports), tested first.
        const uint32_t bad_interrupt = image.require("__bad_interrupt").address;
        const auto jump = hil::avr::decode_flow(image.text_word_or_erased(bad_interrupt), image.text_word_or_erased(bad_interrupt + 2),
                                                bad_interrupt);
        EXPECT_EQ(jump.kind, hil::avr::Flow::Kind::kJump) << elf;
        EXPECT_EQ(jump.target, 0U) << elf;
        EXPECT_NE(std::find(report.unresolved_weak.begin(), report.unresolved_weak.end(), "serialEvent()"),
                  report.unresolved_weak.end())
            << elf;
    }
    // The reference sketch's serialEventRun: `ldi r24, 0; ldi r25, 0; or r24, r25; breq` past its `jmp 0`.
    const auto reference = hil::ElfImage::read(firmware_elf());
    EXPECT_EQ(hil::find_zero_calls(reference).unresolved_weak, std::vector<std::string>{"serialEvent()"});
    const auto run = reference.require("_Z14serialEventRunv");
    EXPECT_EQ(reference.text_word_or_erased(run.address + run.size - 6), 0x940C);  // jmp
    EXPECT_EQ(reference.text_word_or_erased(run.address + run.size - 4), 0x0000);  // 0
}

}  // namespace
}  // namespace ddmr::test
