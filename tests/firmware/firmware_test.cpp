// The firmware under test: the sketch is the thesis's, byte for byte, and the
// ELF the build made from it has what the HIL relies on.
#include <gtest/gtest.h>

#include "common/sha256.hpp"
#include "hil/elf_image.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

// SHA-256 of ../shared/reference/ddmr_tracking.ino (sha256sum), pinned so that
// a change to either copy fails here, not silently in a later run.
constexpr const char* kReferenceSketchSha256 =
    "242749a59a609b5a31babc1abdfec3c528a1726fce3029c4e4bc5adf2c18d796";

TEST(Firmware, SketchIsByteIdenticalToTheReference) {
    const auto ours = tools::sha256_file_hex(source_dir() / "firmware/ddmr_tracking/ddmr_tracking.ino");
    const auto reference = tools::sha256_file_hex(shared_dir() / "reference/ddmr_tracking.ino");
    EXPECT_EQ(ours, reference);
    EXPECT_EQ(ours, kReferenceSketchSha256);
}

TEST(Firmware, ElfIsForTheAtmega328p) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    EXPECT_NO_THROW(elf.require_mcu(hil::atmega328p_mcu()));
    // The thesis (ch. 6) reports about 30 % of the Uno's 32256 usable bytes.
    const double flash_share = elf.memory_use().flash_bytes() / 32256.0;
    EXPECT_GT(flash_share, 0.28);
    EXPECT_LT(flash_share, 0.32);
    EXPECT_LT(elf.memory_use().ram_bytes(), 2048u);
}

TEST(Firmware, ElfHasTheFunctionsTheHilWatches) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    // encoder1()/encoder2() keep their C++-mangled names; with LTO, setup()
    // and loop() are inlined into main.
    for (const char* name : {"_Z8encoder1v", "_Z8encoder2v", "__vector_1", "__vector_2", "delay", "main"}) {
        const auto sym = elf.find(name);
        ASSERT_TRUE(sym.has_value()) << name;
        EXPECT_TRUE(sym->is_function) << name;
        EXPECT_GT(sym->size, 0u) << name;
    }
    EXPECT_FALSE(elf.find("setup").has_value());
    EXPECT_FALSE(elf.find("loop").has_value());
}

TEST(Firmware, ElfHasTheGlobalsTheHilReads) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    // unsigned long Count1, Count2 and float Ex, Ey, Theta: 4 bytes each on AVR,
    // in SRAM (0x100..0x8FF once avr-gcc's 0x800000 data offset is removed).
    for (const char* name : {"Count1", "Count2", "Ex", "Ey", "Theta"}) {
        const auto sym = elf.find(name);
        ASSERT_TRUE(sym.has_value()) << name;
        EXPECT_TRUE(sym->is_object) << name;
        EXPECT_EQ(sym->size, 4u) << name;
        EXPECT_GE(sym->address, 0x100u) << name;
        EXPECT_LE(sym->address, 0x8FFu) << name;
    }
}

}  // namespace
}  // namespace ddmr::test
