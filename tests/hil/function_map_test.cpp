// FunctionMap: entry points and aliases from the ELF's symbols; addresses
// checked against `avr-nm -S -n` / `avr-readelf -s` of the reference build.
#include "hil/function_map.hpp"

#include <gtest/gtest.h>

#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

using hil::FunctionMap;

const std::string& name_at(const FunctionMap& map, uint32_t address) {
    return map.function(map.at(address)).name;
}

TEST(FunctionMap, ReferenceFirmwareEntryPoints) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const FunctionMap map(elf, hil::atmega328p_mcu());
    // libgcc's float add: __subsf3 (FUNC, 14 bytes at 0x1ff8) is one
    // instruction that falls into the global label __addsf3 at 0x1ffa.
    const auto add = map.find("__addsf3");
    ASSERT_TRUE(add.has_value());
    EXPECT_EQ(map.at(0x1ffa), *add);
    EXPECT_EQ(map.at(0x2026), *add);  // the last word before __addsf3x
    EXPECT_TRUE(map.is_entry(0x1ffa));
    EXPECT_FALSE(map.is_entry(0x1ffc));
    const auto& sub = map.function(map.at(0x1ff8));
    EXPECT_EQ(sub.name, "__subsf3");
    EXPECT_EQ(sub.end, 0x1ffau);  // not 0x1ff8 + 14: the next entry point ends it
    EXPECT_EQ(name_at(map, 0x2028), "__addsf3x");
    // Entry labels inside a FUNC symbol split it: __divsf3_pse, __fp_splitA.
    EXPECT_EQ(name_at(map, 0x2114), "__divsf3_pse");
    EXPECT_EQ(name_at(map, 0x23d6), "__fp_splitA");
    EXPECT_EQ(name_at(map, 0x2110), "__divsf3x");
    // Compiled functions, local ones (LTO) too.
    EXPECT_EQ(name_at(map, 0x0ab8), "main");
    EXPECT_EQ(name_at(map, 0x1f4c), "main");
    EXPECT_EQ(name_at(map, 0x05b6), "delay");
    EXPECT_EQ(name_at(map, 0x24fc), "sin");
    EXPECT_EQ(name_at(map, 0x20dc), "cos");
    EXPECT_EQ(name_at(map, 0x2422), "__mulsf3");
}

TEST(FunctionMap, ReferenceFirmwareAliasesHaveOneCanonicalName) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const FunctionMap map(elf, hil::atmega328p_mcu());
    // 0x20d2: __cmpsf2 is the FUNC with a size; the NOTYPE labels are aliases.
    const auto& cmp = map.function(map.at(0x20d2));
    EXPECT_EQ(cmp.name, "__cmpsf2");
    EXPECT_EQ(cmp.aliases, (std::vector<std::string>{"__eqsf2", "__lesf2", "__ltsf2", "__nesf2"}));
    EXPECT_EQ(map.find("__ltsf2"), map.at(0x20d2));
    // 0x2418: __gesf2 (FUNC, size 10) over __gtsf2 (NOTYPE).
    EXPECT_EQ(name_at(map, 0x2418), "__gesf2");
    // 0x0128: global __bad_interrupt over the 20 weak __vector_N aliases.
    const auto& bad = map.function(map.at(0x0128));
    EXPECT_EQ(bad.name, "__bad_interrupt");
    EXPECT_EQ(bad.aliases.size(), 20u);
    // 0x2602: global _exit over weak exit.
    EXPECT_EQ(name_at(map, 0x2602), "_exit");
    EXPECT_EQ(map.function(map.at(0x2602)).aliases, std::vector<std::string>{"exit"});
    // 0x0000: global __vectors over weak __vector_default.
    EXPECT_EQ(name_at(map, 0x0000), "__vectors");
    // 0x00d8: the start-up code is __init; __ctors_end, __dtors_start and
    // __dtors_end there are linker markers, not aliases.
    const auto& init = map.function(map.at(0x00d8));
    EXPECT_EQ(init.name, "__init");
    EXPECT_TRUE(init.aliases.empty());
}

TEST(FunctionMap, ReferenceFirmwareDataAndLabelsAreNotFunctions) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const FunctionMap map(elf, hil::atmega328p_mcu());
    // PROGMEM tables (STT_OBJECT in .text), local labels, linker markers and
    // absolute symbols are not functions.
    for (const char* name : {"port_to_mode_PGM", "digital_pin_to_timer_PGM", ".do_clear_bss_loop",
                             "__udivmodsi4_loop", "__stop_program", "__trampolines_start", "__ctors_start",
                             "_etext", "__heap_end", "__stack"}) {
        EXPECT_FALSE(map.find(name).has_value()) << name;
    }
    EXPECT_EQ(name_at(map, 0x0086), "__vectors");         // port_to_mode_PGM's bytes
    EXPECT_EQ(name_at(map, 0x0102), "__do_clear_bss");    // .do_clear_bss_loop
    EXPECT_EQ(name_at(map, 0x25b4), "__udivmodsi4");      // __udivmodsi4_loop
    EXPECT_EQ(name_at(map, 0x2604), "_exit");             // __stop_program
    // Past .text: the .data image in flash, then erased flash.
    EXPECT_EQ(elf.text_end(), 0x2606u);
    EXPECT_EQ(map.at(0x2606), map.outside());
    EXPECT_EQ(map.at(0x7ffe), map.outside());
    EXPECT_EQ(map.at(0x10000), map.outside());
    EXPECT_EQ(map.function(map.outside()).name, FunctionMap::kOutsideName);
}

TEST(FunctionMap, EveryFunctionSymbolIsAnEntryPointAndTheMapIsContiguous) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const FunctionMap map(elf, hil::atmega328p_mcu());
    std::size_t funcs = 0;
    for (const auto& s : elf.symbols()) {
        if (!s.is_function || !s.in_text) continue;
        ++funcs;
        EXPECT_TRUE(map.is_entry(s.address)) << s.name;
    }
    EXPECT_GT(funcs, 60u);
    // Functions tile .text in address order: each ends where the next begins.
    const auto& fs = map.functions();
    ASSERT_GE(fs.size(), 2u);
    EXPECT_EQ(fs.front().address, 0u);
    for (std::size_t i = 0; i + 2 < fs.size(); ++i) EXPECT_EQ(fs[i].end, fs[i + 1].address) << fs[i].name;
    EXPECT_EQ(fs[fs.size() - 2].end, elf.text_end());
}

TEST(FunctionMap, FixtureFunctions) {
    // tests/firmware/profile_fixture.c, avr-nm -n: leaf 0x80, middle 0x8a,
    // tailer 0x94, mark 0x9a, __vector_1 0xa0, main 0xaa, _exit 0xc2.
    const auto elf = hil::ElfImage::read(test_firmware_dir() / "profile_fixture.elf");
    const FunctionMap map(elf, hil::atmega328p_mcu());
    std::vector<std::string> names;
    for (const auto& f : map.functions()) names.push_back(f.name);
    EXPECT_EQ(names, (std::vector<std::string>{"__vectors", "__init", "__bad_interrupt", "leaf", "middle", "tailer",
                                               "mark", "__vector_1", "main", "_exit", FunctionMap::kOutsideName}));
    EXPECT_EQ(map.function(*map.find("tailer")).end, 0x9au);
}

}  // namespace
}  // namespace ddmr::test
