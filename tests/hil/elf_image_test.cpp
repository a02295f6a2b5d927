// ElfImage: reading firmware ELFs and refusing anything that is not an
// ATmega328P program, with a message that names the file and the problem.
#include "hil/elf_image.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <random>

#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

std::string read_error(const std::filesystem::path& p, bool check_mcu = true) {
    try {
        const auto elf = hil::ElfImage::read(p);
        if (check_mcu) elf.require_mcu(hil::atmega328p_mcu());
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

void write_bytes(const std::filesystem::path& p, const std::string& bytes) {
    std::ofstream(p, std::ios::binary) << bytes;
}

TEST(ElfImage, ReadsTheReferenceFirmware) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    EXPECT_EQ(elf.machine(), 83);  // EM_AVR
    EXPECT_EQ(elf.flags() & 0x7Fu, 5u);  // avr5
    EXPECT_FALSE(elf.mmcu().has_value());  // Arduino sketches have no simavr .mmcu section
    // avr-size reports .text + .data as flash use; 9864 bytes for this sketch
    // with Debian's core, as arduino-builder prints.
    EXPECT_EQ(elf.memory_use().flash_bytes(), 9864u);
    const auto main_fn = elf.require("main");
    const auto at = elf.function_at(main_fn.address + 2);
    ASSERT_TRUE(at.has_value());
    EXPECT_EQ(at->name, "main");
}

TEST(ElfImage, MissingFileIsNamed) {
    TempDir dir;
    const auto msg = read_error(dir / "nope.elf");
    EXPECT_NE(msg.find("nope.elf"), std::string::npos) << msg;
    EXPECT_NE(msg.find("no such file"), std::string::npos) << msg;
}

TEST(ElfImage, EmptyFileIsRefused) {
    TempDir dir;
    write_bytes(dir / "empty.elf", "");
    EXPECT_NE(read_error(dir / "empty.elf").find("empty file"), std::string::npos);
}

TEST(ElfImage, FolderIsRefused) {
    TempDir dir;
    EXPECT_NE(read_error(dir.path()).find("is a folder"), std::string::npos);
}

TEST(ElfImage, RandomBytesAreNotAnElf) {
    TempDir dir;
    std::mt19937 rng(42);
    std::string junk(4096, '\0');
    for (auto& c : junk) c = static_cast<char>(rng() & 0xFF);
    write_bytes(dir / "junk.elf", junk);
    EXPECT_NE(read_error(dir / "junk.elf").find("not an ELF file"), std::string::npos);
}

TEST(ElfImage, TruncatedElfIsRefused) {
    TempDir dir;
    std::ifstream in(firmware_elf(), std::ios::binary);
    std::string head(200, '\0');
    in.read(head.data(), static_cast<std::streamsize>(head.size()));
    write_bytes(dir / "truncated.elf", head);
    const auto msg = read_error(dir / "truncated.elf");
    EXPECT_NE(msg.find("truncated.elf"), std::string::npos) << msg;
    EXPECT_FALSE(msg.empty());
}

TEST(ElfImage, HostElfIsNotAnAvrFirmware) {
    const auto self = std::filesystem::read_symlink("/proc/self/exe");
    const auto msg = read_error(self);
    EXPECT_NE(msg.find("not AVR"), std::string::npos) << msg;
}

TEST(ElfImage, OtherAvrArchitecturesAreRefused) {
    // avr6 (ATmega2560) and avr25 (ATtiny85): the architecture says so.
    EXPECT_NE(read_error(test_firmware_dir() / "other_mcu_atmega2560.elf").find("avr6"),
              std::string::npos);
    EXPECT_NE(read_error(test_firmware_dir() / "other_mcu_attiny85.elf").find("avr25"),
              std::string::npos);
}

TEST(ElfImage, AMismatchNamesTheBoardAndTheElfsArchitecture) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "other_mcu_atmega2560.elf");
    try {
        elf.require_mcu(hil::atmega328p_mcu(), "uno");
        FAIL() << "an ATmega2560 ELF passed as the Uno's";
    } catch (const std::runtime_error& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("avr6 (e.g. the ATmega2560)"), std::string::npos) << m;
        EXPECT_NE(m.find("board 'uno' (ATmega328P) is avr5"), std::string::npos) << m;
        // The board it was likely built for is named first.
        EXPECT_NE(m.find("if it was built for the mega2560, give that board (board: KEY in the board file, or run "
                         "--board-name KEY); else build it for the ATmega328P"),
                  std::string::npos)
            << m;
        EXPECT_EQ(m.find('\n'), std::string::npos) << m;  // one line
    }
}

TEST(ElfImage, OtherAvr5McuIsRefusedByItsVectorTable) {
    // The ATmega32U4 is avr5 like the ATmega328P but has 43 vectors.
    const auto msg = read_error(test_firmware_dir() / "other_mcu_atmega32u4.elf");
    EXPECT_NE(msg.find("more than 26 interrupt vectors"), std::string::npos) << msg;
}

TEST(ElfImage, RequireNamesTheMissingSymbol) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    try {
        (void)elf.require("no_such_function");
        FAIL() << "require() accepted a missing symbol";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no_such_function"), std::string::npos);
    }
}

// A C++ name is its demangled form without the parameter list (what a user
// types: `MyClass::step`, `serialEventRun`), or whole where overloads share it.
TEST(ElfImage, WithoutParametersKeepsTheQualifiedName) {
    EXPECT_EQ(hil::without_parameters("serialEventRun()"), "serialEventRun");
    EXPECT_EQ(hil::without_parameters("ns::MyClass::step(int) const"), "ns::MyClass::step");
    EXPECT_EQ(hil::without_parameters("(anonymous namespace)::f(int)"), "(anonymous namespace)::f");
    EXPECT_EQ(hil::without_parameters("C::operator()(int) &&"), "C::operator()");
    EXPECT_EQ(hil::without_parameters("f(void (*)(int))"), "f");
    EXPECT_EQ(hil::without_parameters("Print::println(double, int) [clone .constprop.10]"), "Print::println");
    EXPECT_EQ(hil::without_parameters("delay"), "delay");
    EXPECT_EQ(hil::without_parameters(""), "");
}

// tests/firmware/cpp_fixture.cpp: MyClass::step(), tick(int) and tick(long),
// serialEventRun() mangled as the Arduino core's.
TEST(ElfImage, FindsFunctionsByTheirCxxNames) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "cpp_fixture.elf");
    const auto names = [&](const std::string& name) {
        std::vector<std::string> out;
        for (const auto& f : elf.find_functions(name)) out.push_back(f.name);
        std::sort(out.begin(), out.end());
        return out;
    };
    using V = std::vector<std::string>;
    EXPECT_EQ(names("serialEventRun"), V{"_Z14serialEventRunv"});
    EXPECT_EQ(names("_Z14serialEventRunv"), V{"_Z14serialEventRunv"});
    EXPECT_EQ(names("serialEventRun()"), V{"_Z14serialEventRunv"});
    EXPECT_EQ(names("MyClass::step"), V{"_ZN7MyClass4stepEv"});
    EXPECT_EQ(names("tick"), (V{"_Z4ticki", "_Z4tickl"}));  // overloads: both
    EXPECT_EQ(names("tick(long)"), V{"_Z4tickl"});
    EXPECT_EQ(names("main"), V{"main"});
    EXPECT_EQ(names("step"), V{});  // a member needs its class
    EXPECT_EQ(names("(anonymous namespace)::sink"), V{});  // a variable is no function
    // The shortest name that finds a function alone.
    const auto name_of = [&](const std::string& symbol) { return elf.function_name(*elf.find(symbol)); };
    EXPECT_EQ(name_of("_Z14serialEventRunv"), "serialEventRun");
    EXPECT_EQ(name_of("_ZN7MyClass4stepEv"), "MyClass::step");
    EXPECT_EQ(name_of("_Z4tickl"), "tick(long)");
    EXPECT_EQ(name_of("main"), "main");
}

TEST(ElfImage, TextWordsAreTheProgramsBytes) {
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "cpp_fixture.elf");
    // Vector 0 is JMP __ctors_end: 0x940C and its word address.
    EXPECT_EQ(elf.text_word(0), 0x940C);
    EXPECT_EQ(elf.text_word(2), elf.require("__ctors_end").address / 2);
    EXPECT_FALSE(elf.text_word(elf.text_end()).has_value());
    EXPECT_FALSE(elf.text_word(elf.text_end() - 1).has_value());  // half a word
    EXPECT_TRUE(elf.text_word(elf.text_end() - 2).has_value());
}

TEST(ElfImage, AWeakSymbolTheLinkLeftUnresolvedIsUndefined) {
    // weak_call_fixture.c: `void hook(void) __attribute__((weak));`, never defined.
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "weak_call_fixture_unguarded.elf");
    const auto hook = elf.require("hook");
    EXPECT_FALSE(hook.defined);
    EXPECT_EQ(hook.binding, hil::ElfBinding::kWeak);
    EXPECT_EQ(hook.address, 0U);
    EXPECT_FALSE(hook.in_text);
    EXPECT_TRUE(elf.require("main").defined);
}

TEST(ElfImage, TextWordsAreTheProgramAsFetched) {
    // The fixture's main is `call 0` (0x940E 0x0000); outside .text reads as erased flash.
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "weak_call_fixture_unguarded.elf");
    const uint32_t main = elf.require("main").address;
    EXPECT_EQ(elf.text_word_or_erased(main), 0x940E);
    EXPECT_EQ(elf.text_word_or_erased(main + 2), 0x0000);
    EXPECT_EQ(elf.text_word_or_erased(0), 0x940C);  // the reset vector's JMP
    EXPECT_EQ(elf.text_word_or_erased(elf.text_end()), 0xFFFF);
    EXPECT_EQ(elf.text_word_or_erased(elf.text_end() - 1), 0xFFFF);  // half a word
}

}  // namespace
}  // namespace ddmr::test
