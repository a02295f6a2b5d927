// FirmwareVariables: byte decoding worked by hand, the reference firmware's
// globals after boot, lookup errors, and the end pose it prints.
#include "hil/firmware_variables.hpp"

#include <gtest/gtest.h>

#include <array>
#include <string>

#include "hil/firmware_report.hpp"
#include "hil/uart_link.hpp"
#include "support/square_wave_input.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

using hil::VarType;

/// The exception message of `f()`, or "" if it did not throw T.
template <typename T, typename F>
std::string thrown_message(F&& f) {
    try {
        f();
    } catch (const T& e) {
        return e.what();
    }
    return "";
}

TEST(FirmwareVariables, DecodesLittleEndianBytesAsAvrGccLaysThemOut) {
    // 0.01f = 0x3C23D70A (sign 0, exponent 120 = 2^-7, mantissa 0x23D70A:
    // 1.28 * 2^-7 = 0.01), stored lowest byte first.
    EXPECT_EQ(hil::decode_var(VarType::kFloat, {0x0A, 0xD7, 0x23, 0x3C}), static_cast<double>(0.01f));
    // 0xFC18 = 64536 unsigned = 64536 - 65536 = -1000 signed.
    EXPECT_EQ(hil::decode_var(VarType::kUint16, {0x18, 0xFC, 0x77, 0x77}), 64536.0);
    EXPECT_EQ(hil::decode_var(VarType::kInt16, {0x18, 0xFC, 0x77, 0x77}), -1000.0);
    // 0xE7 = 231 unsigned = 231 - 256 = -25 signed.
    EXPECT_EQ(hil::decode_var(VarType::kUint8, {0xE7, 0x77, 0x77, 0x77}), 231.0);
    EXPECT_EQ(hil::decode_var(VarType::kInt8, {0xE7, 0x77, 0x77, 0x77}), -25.0);
    EXPECT_EQ(hil::decode_var(VarType::kUint32, {0x78, 0x56, 0x34, 0x12}), 305419896.0);  // 0x12345678
    EXPECT_EQ(hil::decode_var(VarType::kUint32, {0xFF, 0xFF, 0xFF, 0xFF}), 4294967295.0);
    EXPECT_EQ(hil::decode_var(VarType::kInt32, {0xFF, 0xFF, 0xFF, 0xFF}), -1.0);
}

TEST(FirmwareVariables, EncodesValuesAsTheBytesDecodeReads) {
    using Bytes = std::array<uint8_t, 4>;
    EXPECT_EQ(hil::encode_var(VarType::kFloat, 0.01), (Bytes{0x0A, 0xD7, 0x23, 0x3C}));  // as above
    EXPECT_EQ(hil::encode_var(VarType::kInt16, -1000), (Bytes{0x18, 0xFC, 0, 0}));
    EXPECT_EQ(hil::encode_var(VarType::kUint32, 305419896.0), (Bytes{0x78, 0x56, 0x34, 0x12}));
    EXPECT_EQ(hil::encode_var(VarType::kInt8, -25), (Bytes{0xE7, 0, 0, 0}));
    EXPECT_EQ(hil::encode_var(VarType::kInt32, -1), (Bytes{0xFF, 0xFF, 0xFF, 0xFF}));
    // What a type cannot hold exactly is refused, naming the value and the type.
    EXPECT_EQ(thrown_message<std::invalid_argument>([] { (void)hil::encode_var(VarType::kUint8, 256); }),
              "256 is not a uint8 (an integer in [0, 255])");
    EXPECT_EQ(thrown_message<std::invalid_argument>([] { (void)hil::encode_var(VarType::kInt16, 0.5); }),
              "0.5 is not a int16 (an integer in [-32768, 32767])");
    EXPECT_EQ(thrown_message<std::invalid_argument>([] { (void)hil::encode_var(VarType::kUint16, -1); }),
              "-1 is not a uint16 (an integer in [0, 65535])");
    EXPECT_EQ(thrown_message<std::invalid_argument>([] { (void)hil::encode_var(VarType::kFloat, 1e39); }),
              "1e+39 is not a finite float (binary32)");
}

TEST(FirmwareVariables, ParsesTypeNames) {
    for (const auto t : {VarType::kInt8, VarType::kUint8, VarType::kInt16, VarType::kUint16,
                         VarType::kInt32, VarType::kUint32, VarType::kFloat}) {
        EXPECT_EQ(hil::parse_var_type(hil::to_string(t)), t);
    }
    EXPECT_EQ(hil::parse_var_type("double"), VarType::kFloat);  // avr-gcc: 32-bit double
    EXPECT_EQ(hil::var_type_size(VarType::kInt16), 2u);
    // "int" is ambiguous on a host (32 bits) and the AVR (16): not accepted.
    const auto msg = thrown_message<std::invalid_argument>([] { (void)hil::parse_var_type("int"); });
    EXPECT_NE(msg.find("'int'"), std::string::npos) << msg;
}

TEST(FirmwareVariables, DefaultTypeBySymbolSize) {
    using hil::FourByteDefault;
    // avr-gcc: char 1 byte, int 2, long and float 4.
    EXPECT_EQ(hil::default_var_type(1, FourByteDefault::kNone), VarType::kUint8);
    EXPECT_EQ(hil::default_var_type(2, FourByteDefault::kNone), VarType::kInt16);
    EXPECT_EQ(hil::default_var_type(4, FourByteDefault::kFloat), VarType::kFloat);
    EXPECT_EQ(hil::default_var_type(4, FourByteDefault::kNone), std::nullopt);  // long or float?
    for (const std::size_t size : {std::size_t{0}, std::size_t{3}, std::size_t{8}}) {
        EXPECT_EQ(hil::default_var_type(size, FourByteDefault::kFloat), std::nullopt) << size;
    }
}

TEST(FirmwareVariables, ReadsTheSketchGlobalsAfterBoot) {
    // After 0.1 s the firmware is inside setup()'s delay(5000): static
    // initialisation and setup() have run. Globals in the ELF (avr-nm -S):
    // dt (4 bytes, .data), k (1, .data), NUM (2, .bss, set by a constructor),
    // Count1 (4, .bss), addr (2, .bss). `endtime` (int, 12) is not there: LTO
    // folded the never-written global into NUM's initialiser, so NUM stands
    // in for it: int(endtime / dt) = int(12 / 0.01f) = int(1200.0000268f) =
    // int(1200.0f) = 1200.
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    core.run_until(hil::s_to_cycles(0.1, kUnoClockHz));
    const hil::FirmwareVariables vars(elf, core);
    EXPECT_EQ(vars.read_float("dt"), 0.01f);  // bit-exact: float dt = 0.01
    EXPECT_EQ(vars.read("dt", VarType::kFloat), static_cast<double>(0.01f));
    EXPECT_EQ(vars.read_u8("k"), 10);          // byte k = 10
    EXPECT_EQ(vars.read_i16("NUM"), 1200);
    EXPECT_EQ(vars.read_u32("Count1"), 0u);    // zeroed in setup(), no edges yet
    EXPECT_EQ(vars.read_i16("addr"), 0);
    // A resolved handle reads the same without a name lookup.
    const hil::Variable k = vars.lookup("k", VarType::kUint8);
    EXPECT_EQ(k.size, 1);
    EXPECT_EQ(vars.read(k), 10.0);
    EXPECT_EQ(vars.read_as<uint8_t>(k), 10);
}

TEST(FirmwareVariables, LookupErrorsNameTheSymbolSizeAndType) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    const hil::FirmwareVariables vars(elf, core);

    // dt is a 4-byte float; int16 is 2 bytes.
    auto msg = thrown_message<std::runtime_error>([&] { (void)vars.lookup("dt", VarType::kInt16); });
    EXPECT_NE(msg.find("'dt'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("4 bytes"), std::string::npos) << msg;
    EXPECT_NE(msg.find("int16"), std::string::npos) << msg;

    msg = thrown_message<std::runtime_error>([&] { (void)vars.read("endtime", VarType::kInt16); });
    EXPECT_NE(msg.find("no symbol 'endtime'"), std::string::npos) << msg;

    // delay() is code, not data.
    msg = thrown_message<std::runtime_error>([&] { (void)vars.lookup("delay", VarType::kUint32); });
    EXPECT_NE(msg.find("'delay' is a function"), std::string::npos) << msg;

    // A handle looked up as uint8 cannot be read as float.
    const auto k = vars.lookup("k", VarType::kUint8);
    msg = thrown_message<std::invalid_argument>([&] { (void)vars.read_as<float>(k); });
    EXPECT_NE(msg.find("'k'"), std::string::npos) << msg;

    // A hand-made handle outside SRAM reads NaN rather than throwing.
    const hil::Variable bogus{"bogus", 0x0900, 4, VarType::kFloat};
    EXPECT_TRUE(std::isnan(vars.read(bogus)));
}

TEST(FirmwareVariables, EndPoseMatchesThePrintedReport) {
    // Square waves on pins 2 and 3 make the firmware integrate a turning
    // motion. After "END" the sketch prints Ex, Ey (and Theta) with 4
    // decimals, then overwrites Ex/Ey in its EEPROM dump loop and zeroes
    // them: so they are read when "END\r\n" has been written to UDR0, which
    // is after the last loop iteration and before any of that.
    // Arduino's Print adds 0.5e-4 and truncates: |printed - value| <= 5e-5
    // (plus float rounding in that sum, < 1e-6 for |value| < 8).
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    const hil::FirmwareVariables vars(elf, core);
    const auto ex = vars.lookup("Ex", VarType::kFloat);
    const auto ey = vars.lookup("Ey", VarType::kFloat);
    const auto theta = vars.lookup("Theta", VarType::kFloat);
    hil::FirmwareReportParser parser(true);
    std::string tail;
    double ex_at_end = 0, ey_at_end = 0, theta_at_end = 0;
    bool seen_end = false;
    uart.set_listener([&](const hil::UartByte& b) {
        const char c = static_cast<char>(b.value);
        parser.feed(std::string_view(&c, 1));
        tail.push_back(c);
        if (tail.size() > 5) tail.erase(0, 1);
        if (!seen_end && tail == "END\r\n") {
            seen_end = true;
            ex_at_end = vars.read(ex);
            ey_at_end = vars.read(ey);
            theta_at_end = vars.read(theta);
        }
        if (parser.complete() || parser.error()) core.request_stop();
    });
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)),
              hil::RunStop::kCondition);
    SquareWaveInput left(core, 'D', 2, 25'000);   // 640 edges/s on Count1
    SquareWaveInput right(core, 'D', 3, 32'000);  // 500 edges/s on Count2
    uart.send("1");
    core.run_until(core.cycle() + hil::s_to_cycles(20.0, kUnoClockHz));
    ASSERT_TRUE(parser.complete()) << uart.text();
    ASSERT_TRUE(seen_end);
    const auto& r = parser.report();
    constexpr double kPrintTolerance = 5e-5 + 1e-6;
    EXPECT_NEAR(ex_at_end, r.ex.value(), kPrintTolerance);
    EXPECT_NEAR(ey_at_end, r.ey.value(), kPrintTolerance);
    EXPECT_NEAR(theta_at_end, r.theta.value(), kPrintTolerance);
    // Not a trivially zero pose: 12 s at ~0.3 m/s on a ~0.52 m circle.
    EXPECT_GT(std::abs(ex_at_end) + std::abs(ey_at_end), 0.1);
    // And afterwards the sketch has reset them (Ex = Ey = 0.0 at the end of case 1).
    EXPECT_EQ(vars.read(ex), 0.0);
    EXPECT_EQ(vars.read(ey), 0.0);
}

}  // namespace
}  // namespace ddmr::test
