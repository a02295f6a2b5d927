// FirmwareReportParser: the reference sketch's end-of-run report, parsed.
#include "hil/firmware_report.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::test {
namespace {

// A case-1 report shaped exactly as the sketch prints it (println ends lines
// with \r\n), with addr = 4: pairs for j = 0, 2, 4.
constexpr const char* kCase1 =
    "0.6m\r\nEND\r\n7652\r\n5813\r\nGx,0.600,Gy,-0.003,t,12.000\r\npdt1,12.34,pdt2,-1.50\r\n"
    "V,0.1234,W,0.2000\r\nEx,0.5650,Ey,-0.1360,Thta,6.2000\r\nex,0.0350,ey,0.1330,exr,0.0100\r\n"
    "4\r\n0.000 , 0.000\r\n0.020 , 0.004\r\n1.020 , 1.020\r\n";

TEST(FirmwareReport, ParsesACase1Report) {
    hil::FirmwareReportParser p(true);
    p.feed(kCase1);
    ASSERT_FALSE(p.error().has_value()) << *p.error();
    ASSERT_TRUE(p.complete());
    const auto& r = p.report();
    EXPECT_EQ(r.banner, "0.6m");
    EXPECT_EQ(*r.count1, 7652);
    EXPECT_EQ(*r.count2, 5813);
    EXPECT_DOUBLE_EQ(*r.gy, -0.003);
    EXPECT_DOUBLE_EQ(*r.pdt2, -1.5);
    EXPECT_DOUBLE_EQ(*r.ex, 0.565);
    EXPECT_DOUBLE_EQ(*r.theta, 6.2);
    EXPECT_DOUBLE_EQ(*r.errxr, 0.01);
    EXPECT_EQ(*r.addr, 4);
    ASSERT_EQ(r.eeprom_pairs.size(), 3u);  // j = 0, 2, 4
    EXPECT_DOUBLE_EQ(r.eeprom_pairs[1].first, 0.02);
    EXPECT_DOUBLE_EQ(r.eeprom_pairs[2].second, 1.02);
}

TEST(FirmwareReport, ByteByByteFeedingGivesTheSameReport) {
    hil::FirmwareReportParser p(true);
    for (const char* c = kCase1; *c != '\0'; ++c) p.feed(std::string_view(c, 1));
    ASSERT_TRUE(p.complete());
    EXPECT_EQ(p.report().eeprom_pairs.size(), 3u);
}

TEST(FirmwareReport, IncompleteUntilTheLastPair) {
    hil::FirmwareReportParser p(true);
    const std::string all(kCase1);
    p.feed(all.substr(0, all.size() - 2));  // last line without its \r\n
    EXPECT_FALSE(p.complete());
    p.feed("\r\n");
    EXPECT_TRUE(p.complete());
}

TEST(FirmwareReport, Case2EndsAfterTheErrorLine) {
    hil::FirmwareReportParser p(false);
    p.feed("0.4m\r\nEND\r\n1\r\n2\r\nGx,0.400,Gy,0.000,t,8.000\r\npdt1,0.00,pdt2,0.00\r\n"
           "V,0.0000,W,0.0000\r\nEx,0.0000,Ey,0.0000,Thta,0.0000\r\n");
    EXPECT_FALSE(p.complete());
    p.feed("ex,0.4000,ey,0.0000,exr,0.4000\r\n");
    EXPECT_TRUE(p.complete());
    EXPECT_EQ(p.report().banner, "0.4m");
    EXPECT_TRUE(p.report().eeprom_pairs.empty());
}

TEST(FirmwareReport, ArduinoSpecialValuesAreKept) {
    hil::FirmwareReportParser p(false);
    p.feed("0.4m\r\nEND\r\n0\r\n0\r\nGx,nan,Gy,inf,t,ovf\r\n");
    ASSERT_FALSE(p.error().has_value());
    EXPECT_TRUE(std::isnan(*p.report().gx));
    EXPECT_TRUE(std::isinf(*p.report().gy));
    EXPECT_TRUE(std::isinf(*p.report().t));
}

TEST(FirmwareReport, MalformedLineIsAnErrorNamingIt) {
    hil::FirmwareReportParser p(true);
    p.feed("0.6m\r\nEND\r\n12\r\n13\r\nGx,0.600,Gy\r\n");
    ASSERT_TRUE(p.error().has_value());
    EXPECT_NE(p.error()->find("line 5"), std::string::npos) << *p.error();
    EXPECT_NE(p.error()->find("Gx,0.600,Gy"), std::string::npos) << *p.error();
    EXPECT_FALSE(p.complete());
}

TEST(FirmwareReport, ChatterBeforeTheBannerIsIgnored) {
    hil::FirmwareReportParser p(false);
    p.feed("X\r\nhello\r\n0.4m\r\n");
    EXPECT_FALSE(p.error().has_value());
    EXPECT_EQ(p.report().banner, "0.4m");
}

TEST(FirmwareReport, OddAddrIsRejected) {
    hil::FirmwareReportParser p(true);
    p.feed(std::string("0.6m\r\nEND\r\n0\r\n0\r\nGx,0,Gy,0,t,0\r\npdt1,0,pdt2,0\r\nV,0,W,0\r\n"
                       "Ex,0,Ey,0,Thta,0\r\nex,0,ey,0,exr,0\r\n3\r\n"));
    ASSERT_TRUE(p.error().has_value());
    EXPECT_NE(p.error()->find("addr"), std::string::npos);
}

}  // namespace
}  // namespace ddmr::test
