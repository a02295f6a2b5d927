// Tests for tools/scenario/junit: the XML CI systems read, parsed back.
#include "scenario/junit.hpp"

#include <gtest/gtest.h>
#include <pugixml.hpp>

namespace ddmr::tools::scenario {
namespace {

TEST(Junit, OneTestcasePerScenarioWithFailuresAndErrors) {
    ScenarioResult pass;
    pass.name = "ok";
    pass.file = "tests/scenarios/ok.yaml";
    pass.wall_seconds = 1.25;
    pass.steps.push_back({4, "delay", "{delay: 1ms}", true, 16000, ""});
    ScenarioResult fail = pass;
    fail.name = "bad";
    fail.verdict = Verdict::kFail;
    fail.message = "x.yaml:7: expect-var failed: expected Count1 >= 7000, got 12 <&>";
    ScenarioResult crash = pass;
    crash.name = "crash";
    crash.verdict = Verdict::kFirmware;
    crash.message = "crashed at PC 0x1234";
    pugi::xml_document doc;
    const std::string xml = junit_xml("suite", {pass, fail, crash});
    ASSERT_TRUE(doc.load_string(xml.c_str())) << xml;
    const auto suite = doc.child("testsuites").child("testsuite");
    EXPECT_EQ(suite.attribute("tests").as_int(), 3);
    EXPECT_EQ(suite.attribute("failures").as_int(), 1);
    EXPECT_EQ(suite.attribute("errors").as_int(), 1);
    EXPECT_DOUBLE_EQ(suite.attribute("time").as_double(), 3.75);
    int cases = 0;
    for (const auto& tc : suite.children("testcase")) {
        ++cases;
        const std::string name = tc.attribute("name").value();
        if (name == "ok") {
            EXPECT_FALSE(tc.child("failure"));
            EXPECT_FALSE(tc.child("error"));
            EXPECT_NE(std::string(tc.child("system-out").text().get()).find("{delay: 1ms}"), std::string::npos);
        } else if (name == "bad") {
            EXPECT_EQ(std::string(tc.child("failure").attribute("message").value()), fail.message);  // escaped and back
        } else {
            EXPECT_EQ(std::string(tc.child("error").attribute("message").value()), crash.message);
        }
    }
    EXPECT_EQ(cases, 3);
}

}  // namespace
}  // namespace ddmr::tools::scenario
