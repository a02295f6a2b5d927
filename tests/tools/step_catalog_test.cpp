// The step catalogue (tools/scenario/step_catalog): the parser accepts
// exactly its kinds, and every example it shows a user is a valid step.
#include "scenario/step_catalog.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <set>
#include <string>

#include "scenario/scenario_yaml.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::tools::scenario {
namespace {

LoadOptions options() {
    LoadOptions o;
    o.reference_firmware = test::firmware_elf();
    return o;
}

TEST(StepCatalog, EveryExampleParsesAsItsKind) {
    // As if in tests/scenarios/ (its golden/ files are there).
    const auto file = test::source_dir() / "tests/scenarios/catalogue.yaml";
    // move-obstacle names an obstacle of its world: as if beside a world with a box.
    test::TempDir dir;
    std::ofstream(dir / "world.yaml") << "walls:\n  - {polygon_m: [[1, -0.1], [1.2, -0.1], [1.2, 0.1], [1, 0.1]], name: box}\n";
    std::set<std::string_view> kinds;
    for (const StepInfo& s : step_catalog()) {
        EXPECT_TRUE(kinds.insert(s.kind).second) << s.kind << " twice";
        // expect-part names a part of its board: as if beside the shield example's.
        const bool part = s.kind == "expect-part";
        const bool obstacle = s.kind == "move-obstacle";
        const std::string text = std::string(part ? "board: board.yaml\n" : "") + (obstacle ? "world: world.yaml\n" : "") +
                                 "timeout: 10s\nsteps:\n  - " + std::string(s.example) + "\n";
        try {
            const Scenario sc = parse_scenario(text,
                                               part       ? test::source_dir() / "firmware/examples/afmotor_shield_v1/catalogue.yaml"
                                               : obstacle ? dir / "catalogue.yaml"
                                                          : file,
                                               options());
            ASSERT_EQ(sc.steps.size(), 1u);
            EXPECT_EQ(sc.steps[0].kind, s.kind);
        } catch (const std::exception& e) {
            ADD_FAILURE() << s.kind << ": " << e.what();
        }
        EXPECT_EQ(find_step(s.kind), &s);
        EXPECT_NE(step_catalog_text().find("  " + std::string(s.kind) + ": "), std::string_view::npos) << s.kind;
    }
    EXPECT_EQ(find_step("dance"), nullptr);
}

TEST(StepCatalog, AnUnknownStepListsTheKnownOnes) {
    try {
        (void)parse_scenario("timeout: 1s\nsteps:\n  - dance: 1ms\n", "/tmp/case.yaml", options());
        FAIL();
    } catch (const std::exception& e) {
        const std::string m = e.what();
        EXPECT_NE(m.find("unknown step (the steps: delay, write-serial, "), std::string::npos) << m;
        EXPECT_NE(m.find(", reset; `ddmr-hil scenario --list-steps` shows their forms)"), std::string::npos) << m;
    }
}

}  // namespace
}  // namespace ddmr::tools::scenario
