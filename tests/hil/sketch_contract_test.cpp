// SketchContract: the reference sketch's contract as shipped, and refusals
// that name file, line and key.
#include "hil/sketch_contract.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

std::filesystem::path reference_contract() {
    return std::filesystem::path(DDMR_TEST_SOURCE_DIR) / "firmware" / "ddmr_tracking" / "hil.yaml";
}

std::string refusal(const std::string& yaml) {
    TempDir dir;
    const auto p = dir / "hil.yaml";
    std::ofstream(p) << yaml;
    try {
        hil::load_sketch_contract(p);
    } catch (const std::exception& e) {
        const std::string m = e.what();
        return m.substr(m.find("hil.yaml"));
    }
    return "";
}

TEST(SketchContract, TheReferenceSketchsContract) {
    const hil::SketchContract c = hil::load_sketch_contract(reference_contract());
    ASSERT_TRUE(c.start.has_value());
    EXPECT_EQ(c.start->after_return, "delay");
    EXPECT_EQ(c.start->cases, (std::vector<int>{1, 2}));
    EXPECT_EQ(c.start_text(2), "2");
    EXPECT_THROW(c.start_text(3), std::invalid_argument);
    EXPECT_EQ(c.report, hil::ReportFormat::kDdmrTracking);
    ASSERT_TRUE(c.complete.has_value());
    EXPECT_TRUE(c.complete->report);
    ASSERT_TRUE(c.pose.has_value());
    EXPECT_EQ(c.pose->x, "Ex");
    EXPECT_EQ(c.pose->at_text, "END");
    EXPECT_EQ(c.loop.marker, "t");
    EXPECT_EQ(c.loop.function, "delay");
    EXPECT_EQ(c.trace.size(), 11u);
    ASSERT_TRUE(c.eeprom_log.has_value());
    // The layout hil/eeprom_log.hpp documents for the sketch: 250 samples fit.
    EXPECT_EQ(c.eeprom_log->y_address, 500);
    EXPECT_EQ(c.eeprom_log->stride, 2);
    EXPECT_DOUBLE_EQ(c.eeprom_log->counts_per_metre, 250.0);
    EXPECT_DOUBLE_EQ(c.eeprom_log->sample_period_s, 0.1);
    EXPECT_EQ(c.eeprom_log->max_samples(1024), 250);
}

TEST(SketchContract, AnEmptyContractSaysNothing) {
    TempDir dir;
    std::ofstream(dir / "hil.yaml") << "# nothing special\n";
    const hil::SketchContract c = hil::load_sketch_contract(dir / "hil.yaml");
    EXPECT_FALSE(c.start || c.complete || c.pose || c.eeprom_log);
    EXPECT_EQ(c.start_text(1), "");
}

TEST(SketchContract, RefusesWithFileLineAndKey) {
    EXPECT_EQ(refusal("begin: {send: x}\n"),
              "hil.yaml:1: key 'begin': unknown key (expected start, complete, report, pose, loop, trace, eeprom-log)");
    EXPECT_EQ(refusal("start:\n  send: go\n"), "hil.yaml:2: key 'start': give exactly one of after-return, at, after-text");
    EXPECT_EQ(refusal("start:\n  send: go\n  at: 5\n"), "hil.yaml:3: key 'start.at': '5' needs a unit: s, ms or us (e.g. 5s)");
    EXPECT_EQ(refusal("start:\n  send: \"{case}\"\n  at: 1s\n"),
              "hil.yaml:2: key 'start.send': {case} needs a cases list (e.g. cases: [1, 2])");
    EXPECT_EQ(refusal("complete: {report: true}\n"),
              "hil.yaml:1: key 'complete.report': needs a report format that knows its end (report: ddmr-tracking); "
              "fields: use complete.text");
    EXPECT_EQ(refusal("report: csv\n"), "hil.yaml:1: key 'report': unknown report format 'csv' (none, ddmr-tracking, or fields: {...})");
    EXPECT_EQ(refusal("report: {fields: {n: \"count [0-9]+\"}}\n"),
              "hil.yaml:1: key 'report.fields.n': the pattern needs a (group) around the number");
    EXPECT_NE(refusal("report: {fields: {n: \"(\"}}\n").find("is not a regular expression"), std::string::npos);
    EXPECT_EQ(refusal("eeprom-log: {x-address: 0, y-address: 500, signed: false, unwrap: true}\n"),
              "hil.yaml:1: key 'eeprom-log.unwrap': unwrapping starts from a signed first sample: not with signed: false");
    EXPECT_EQ(refusal("pose: {x: a, y: b}\n"), "hil.yaml:1: key 'pose.theta': missing: the float global that holds it");
    EXPECT_EQ(refusal("eeprom-log: {x-address: 0, y-address: 5000}\n"),
              "hil.yaml:1: key 'eeprom-log.y-address': 5000 is outside [0, 4095]");  // the largest EEPROM (Mega)
    EXPECT_EQ(refusal("eeprom-log: {x-address: 10, y-address: 10}\n"),
              "hil.yaml:1: key 'eeprom-log': the x and y series leave no room for a sample");
    EXPECT_EQ(refusal("start: [\n"), refusal("start: [\n"));  // malformed YAML: named, with its line
    EXPECT_NE(refusal("start: [\n").find("malformed YAML"), std::string::npos);
}

}  // namespace
}  // namespace ddmr::test
