// Tests for tools/scenario/suite_results: finish_suite, the end that
// `scenario` and `merge` share (verdicts, results.json, JUnit, exit code).
#include "scenario/suite_results.hpp"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <iterator>

#include "exit_codes.hpp"
#include "scenario/junit.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::tools::scenario {
namespace {

namespace fs = std::filesystem;

std::vector<ScenarioResult> two_results(Verdict second) {
    ScenarioResult a;
    a.name = "first";
    a.file = "tests/scenarios/first.yaml";
    a.sim_seconds = 1.5;
    a.wall_seconds = 0.3;
    ScenarioResult b = a;
    b.name = "second";
    b.file = "tests/scenarios/second.yaml";
    b.verdict = second;
    b.message = second == Verdict::kPass ? "" : "second.yaml:4: wait-serial failed at t=0.5 s: crashed at PC 0x0000";
    return {a, b};
}

TEST(SuiteResults, FinishSuitePrintsWritesAndReturnsTheExitCode) {
    test::TempDir dir;
    const auto results = two_results(Verdict::kFirmware);
    ::testing::internal::CaptureStdout();
    const int code = finish_suite(results, dir.path(), dir / "junit.xml");
    const std::string out = ::testing::internal::GetCapturedStdout();
    EXPECT_EQ(code, kExitFirmware);
    EXPECT_EQ(out,
              "PASS  first (tests/scenarios/first.yaml: 1.500 s simulated, 0.3 s wall)\n"
              "ERROR second (tests/scenarios/second.yaml: 1.500 s simulated, 0.3 s wall)\n"
              "      second.yaml:4: wait-serial failed at t=0.5 s: crashed at PC 0x0000\n"
              "1 of 2 scenarios passed\n");
    EXPECT_EQ(test::read_text(dir / "results.json"), suite_results_json(results).dump(2) + "\n");
    EXPECT_EQ(test::read_text(dir / "junit.xml"), junit_xml("ddmr-hil scenarios", results));
}

TEST(SuiteResults, FinishSuiteWithoutJunitPath) {
    test::TempDir dir;
    ::testing::internal::CaptureStdout();
    EXPECT_EQ(finish_suite(two_results(Verdict::kFail), dir.path(), {}), kExitCheckFailed);
    ::testing::internal::GetCapturedStdout();
    EXPECT_TRUE(fs::exists(dir / "results.json"));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir.path()), fs::directory_iterator{}), 1);
    ::testing::internal::CaptureStdout();
    EXPECT_EQ(finish_suite(two_results(Verdict::kPass), dir.path(), {}), kExitOk);
    EXPECT_EQ(::testing::internal::GetCapturedStdout().substr(0, 6), "PASS  ");
}

}  // namespace
}  // namespace ddmr::tools::scenario
