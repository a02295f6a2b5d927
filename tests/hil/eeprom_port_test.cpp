// EepromPort: what the firmware logged, and what a preload shows it.
#include "hil/eeprom_port.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "support/reference_run.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {
namespace {

TEST(EepromPort, Case1LogsEveryOtherByteOfTwoBlocks) {
    // Case 1 runs 1200 iterations and logs every 10th: 120 calls writing
    // int(Ex*250) at addr and int(Ey*250) at addr+500, addr = 0, 2, ..., 238.
    // With no plant the robot does not move: every logged byte is 0; every
    // other byte keeps the erased value 0xFF.
    const auto run = run_reference_case('1');
    ASSERT_TRUE(run.report_complete);
    for (std::size_t i = 0; i < run.eeprom.size(); ++i) {
        const bool logged = (i % 2 == 0) && ((i <= 238) || (i >= 500 && i <= 738));
        EXPECT_EQ(run.eeprom[i], logged ? 0x00 : 0xFF) << "byte " << i;
    }
    EXPECT_EQ(run.report.addr.value_or(-1), 240);
}

TEST(EepromPort, PreloadIsWhatTheFirmwareReads) {
    // Bytes 240 and 740 are never written by case 1 but are printed as its
    // last pair (j <= addr): 125 / 250 = 0.5 and 50 / 250 = 0.2.
    auto image = hil::EepromPort::erased(hil::atmega328p_mcu());
    image[240] = 125;
    image[740] = 50;
    const auto run = run_reference_case('1', hil::UartTiming::kChip, image);
    ASSERT_TRUE(run.report_complete);
    ASSERT_EQ(run.report.eeprom_pairs.size(), 121u);
    EXPECT_DOUBLE_EQ(run.report.eeprom_pairs.back().first, 0.5);
    EXPECT_DOUBLE_EQ(run.report.eeprom_pairs.back().second, 0.2);
    EXPECT_EQ(run.eeprom[240], 125);
    EXPECT_EQ(run.eeprom[740], 50);
}

TEST(EepromPort, ReadBackEqualsPreload) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    hil::EepromPort port(core);
    EXPECT_EQ(port.read_all(), hil::EepromPort::erased(hil::atmega328p_mcu()));  // a new chip
    hil::EepromImage image(hil::atmega328p_mcu().eeprom_bytes, 0);
    for (std::size_t i = 0; i < image.size(); ++i) image[i] = static_cast<uint8_t>(i * 7);
    port.preload(image);
    EXPECT_EQ(port.read_all(), image);
}

TEST(EepromPort, ImageFileMustHold1024Bytes) {
    TempDir dir;
    std::ofstream(dir / "short.bin", std::ios::binary) << std::string(1000, '\xFF');
    try {
        (void)hil::EepromPort::load_image(dir / "short.bin", hil::atmega328p_mcu());
        FAIL() << "a 1000-byte image was accepted";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("1000 bytes"), std::string::npos) << e.what();
    }
    std::ofstream(dir / "ok.bin", std::ios::binary) << std::string(1024, '\x11');
    EXPECT_EQ(hil::EepromPort::load_image(dir / "ok.bin", hil::atmega328p_mcu())[1023], 0x11);
}

}  // namespace
}  // namespace ddmr::test
