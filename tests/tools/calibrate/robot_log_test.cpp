// The robot's serial dump read back: a dump written by hand, the refusals,
// and the reference firmware's own output in the HIL (its dump must give
// back the EEPROM bytes it logged, and its encoder totals).
#include "calibrate/robot_log.hpp"

#include <gtest/gtest.h>

#include <string>

#include "support/reference_run.hpp"

namespace ddmr::calibrate {
namespace {

constexpr const char* kDump =
    "0.6m\r\n"
    "something the robot printed while driving\r\n"
    "END\r\n"
    "7548\r\n"
    "5659\r\n"
    "Gx,0.585,Gy,-0.112,t,12.000\r\n"
    "Ex,0.5343,Ey,-0.0218,Thta,7.8159\r\n"
    "6\r\n"
    "0.000 , 0.000\r\n"
    "0.024 , 1.020\r\n"
    "0.136 , 0.004\r\n"
    "1.020 , 1.020\r\n";

TEST(RobotLog, ReadsTheCountsTheReportAndTheBytes) {
    const RobotLog log = parse_robot_log(kDump, "robot.txt");
    EXPECT_EQ(log.case_number, 1);
    EXPECT_EQ(log.count1, 7548u);
    EXPECT_EQ(log.count2, 5659u);
    EXPECT_DOUBLE_EQ(log.fields.at("Gy"), -0.112);
    EXPECT_DOUBLE_EQ(log.fields.at("Thta"), 7.8159);
    EXPECT_EQ(log.addr, 6u);
    ASSERT_EQ(log.samples.size(), 3u);  // the fourth line is the unwritten byte at addr
    ASSERT_TRUE(log.unwritten.has_value());
    EXPECT_EQ(log.unwritten->x_byte, 255);
    EXPECT_EQ(log.unwritten->line, 12);
    EXPECT_TRUE(log.warnings.empty());
    EXPECT_EQ(log.samples[1].x_byte, 6);    // 0.024 x 250
    EXPECT_EQ(log.samples[1].y_byte, 255);  // 1.020 x 250
    EXPECT_EQ(log.samples[2].x_byte, 34);
    EXPECT_EQ(log.samples[2].y_byte, 1);
    EXPECT_EQ(log.samples[2].line, 11);
}

// A dump copied from a serial monitor often lacks its last line, the byte
// at addr the run never wrote: with addr printed, one line fewer than it
// promises is read as all samples, and said in one line.
TEST(RobotLog, AddrWithoutTheLastLineIsReadWithAWarning) {
    std::string text = kDump;
    text.resize(text.size() - std::string("1.020 , 1.020\r\n").size());
    const RobotLog log = parse_robot_log(text, "robot.txt");
    ASSERT_EQ(log.samples.size(), 3u);  // j = 0, 2, 4: the same samples as with the line
    EXPECT_EQ(log.samples[2].x_byte, 34);
    EXPECT_EQ(log.samples[2].line, 11);
    EXPECT_FALSE(log.unwritten.has_value());
    ASSERT_EQ(log.warnings.size(), 1u);
    EXPECT_EQ(log.warnings[0], "robot.txt: addr 6 promises 4 dump lines, the file has 3: read as the dump without its "
                               "last line (the byte at addr, which the run never wrote), 3 logged samples");
    // Without addr the reader cannot tell: the last line is the unwritten byte.
    const RobotLog old = parse_robot_log("END\n1\n2\n0.000 , 0.000\n0.004 , 0.008\n0.500 , 0.500\n", "old.txt");
    EXPECT_EQ(old.samples.size(), 2u);
    EXPECT_TRUE(old.warnings.empty());
}

TEST(RobotLog, AnOlderBuildsShortReportIsEnough) {
    // No banner, no report lines, no addr: END, the totals and the dump.
    const RobotLog log = parse_robot_log("END\n12\n34\n0.000 , 0.000\n0.004 , 0.008\n0.500 , 0.500\n", "old.txt");
    EXPECT_FALSE(log.case_number);
    EXPECT_EQ(log.count1, 12u);
    EXPECT_EQ(log.count2, 34u);
    EXPECT_FALSE(log.addr);
    EXPECT_TRUE(log.fields.empty());
    ASSERT_EQ(log.samples.size(), 2u);
    EXPECT_EQ(log.samples[1].y_byte, 2);
}

std::string refusal(const std::string& text) {
    try {
        parse_robot_log(text, "r.txt");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(RobotLog, RefusesWhatIsNotOneRunsDump) {
    EXPECT_EQ(refusal("0.6m\n1\n2\n"), "r.txt: no END line: not the end of a run of the reference sketch (END, "
                                        "Count1, Count2, then the EEPROM dump)");
    EXPECT_EQ(refusal("END\nabc\n"), "r.txt:2: expected Count1 (a whole number of encoder edges) after END, got 'abc'");
    EXPECT_EQ(refusal("END\n5\n"), "r.txt:1: the file ends before Count2 (after END)");
    EXPECT_EQ(refusal("END\n5\n6\n0.000 , 0.000\n0.000 , 0.000\n"),
              "r.txt: the EEPROM dump has 2 line(s) 'x , y' after END; at least 3 (2 logged samples and the "
              "unwritten byte at addr) are needed to calibrate");
    EXPECT_EQ(refusal("END\n5\n6\n0.000 , 0.001\n0.000 , 0.000\n"),
              "r.txt:4: '0.000 , 0.001': 0.001 is not an EEPROM byte over 250 (0, 0.004, ..., 1.020)");
    EXPECT_EQ(refusal("END\n5\n6\n1.024 , 0.000\n0.000 , 0.000\n"),
              "r.txt:4: '1.024 , 0.000': 1.024 is not an EEPROM byte over 250 (0, 0.004, ..., 1.020)");
    EXPECT_EQ(refusal("END\n5\n6\n10\n0.000 , 0.000\n0.000 , 0.000\n0.000 , 0.000\n"),
              "r.txt: addr 10 promises 6 dump lines, the file has 3 (a cut log? only the last, the unwritten "
              "byte at addr, may be missing)");
    // One line fewer than addr promises is the missing last line (a warning,
    // AddrWithoutTheLastLine...); two fewer is a cut log.
    EXPECT_EQ(refusal("END\n5\n6\n10\n0.000 , 0.000\n0.000 , 0.000\n0.000 , 0.000\n0.000 , 0.000\n"),
              "r.txt: addr 10 promises 6 dump lines, the file has 4 (a cut log? only the last, the unwritten "
              "byte at addr, may be missing)");
    EXPECT_EQ(refusal("END\n5\n6\n0.000 , 0.000\n0.000 , 0.000\nEND\n"),
              "r.txt:6: a second END (the first is on line 1): the file holds more than one run; give each run its "
              "own file");
    EXPECT_EQ(refusal("END\n5\n6\nhello world\n"),
              "r.txt:4: 'hello world' is neither a report line (Key,value,...), addr, nor a dump line 'x , y'");
    EXPECT_EQ(refusal("END\n5\n6\n0.000 , 0.000\n0.000 , 0.000\nok\n0.000 , 0.000\n"),
              "r.txt:7: dump line '0.000 , 0.000' after the dump ended: the dump must be contiguous");
    EXPECT_NE(refusal("").find("no END line"), std::string::npos);
}

TEST(RobotLog, AMissingFileIsOneLine) {
    try {
        read_robot_log("/nonexistent/robot.txt");
        FAIL();
    } catch (const std::runtime_error& e) {
        EXPECT_STREQ(e.what(), "/nonexistent/robot.txt: cannot read the log (missing or unreadable)");
    }
}

// The reference sketch's own serial output (case 1 in the HIL) is such a
// dump: its lines give back the EEPROM bytes at 2k and 2k + 500 and the
// report's encoder totals.
TEST(RobotLog, TheReferenceFirmwaresDumpGivesBackItsEepromBytes) {
    const test::ReferenceRun run = test::run_reference_case('1');
    ASSERT_TRUE(run.report_complete);
    const RobotLog log = parse_robot_log(run.text, "uart.txt");
    EXPECT_EQ(log.case_number, 1);
    EXPECT_EQ(static_cast<double>(log.count1), run.report.count1.value());
    EXPECT_EQ(static_cast<double>(log.count2), run.report.count2.value());
    ASSERT_TRUE(log.addr.has_value());
    ASSERT_EQ(log.samples.size(), static_cast<std::size_t>(*log.addr / 2));  // the last dump line is not a sample
    ASSERT_GT(log.samples.size(), 100u);
    for (std::size_t k = 0; k < log.samples.size(); ++k) {
        EXPECT_EQ(log.samples[k].x_byte, run.eeprom.at(2 * k)) << k;
        EXPECT_EQ(log.samples[k].y_byte, run.eeprom.at(2 * k + 500)) << k;
    }
    EXPECT_DOUBLE_EQ(log.fields.at("Ex"), run.report.ex.value());
    // The same dump without its last line (the byte at addr): the same samples, and a warning.
    const std::size_t last = run.text.rfind('\n', run.text.size() - 2);
    ASSERT_NE(last, std::string::npos);
    const RobotLog cut = parse_robot_log(run.text.substr(0, last + 1), "uart.txt");
    ASSERT_EQ(cut.samples.size(), log.samples.size());
    for (std::size_t k = 0; k < cut.samples.size(); ++k) {
        EXPECT_EQ(cut.samples[k].x_byte, log.samples[k].x_byte) << k;
        EXPECT_EQ(cut.samples[k].y_byte, log.samples[k].y_byte) << k;
    }
    EXPECT_FALSE(cut.unwritten.has_value());
    EXPECT_EQ(cut.warnings.size(), 1u);
}

}  // namespace
}  // namespace ddmr::calibrate
