// The mutation check of issue 7: the shipped scenarios (tests/scenarios/*.yaml)
// must catch real firmware regressions. The reference firmware passes every
// one of them; each mutant (tests/mutants/<name>.patch, built to
// build/mutants/<name>.elf) must make at least one fail. Each run prints which
// scenarios caught the mutant and the one-line message they gave.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// The six variants the requirement names; each must have its patch.
const std::vector<std::string> kRequiredVariants = {"kx_float",        "encoder_pins_swapped", "delay_5",
                                                    "no_eeprom_writes", "ky_sign_flipped",      "baud_19200"};

fs::path mutants_source_dir() { return source_dir() / "tests" / "mutants"; }
fs::path mutant_elf(const std::string& name) { return fs::path(DDMR_TEST_MUTANTS_DIR) / (name + ".elf"); }

/// The files of `dir` ending in `extension`, sorted.
std::vector<fs::path> files_with_extension(const fs::path& dir, const std::string& extension) {
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir)) {
        if (entry.is_regular_file() && entry.path().extension() == extension) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    return files;
}

/// Every variant with a patch in tests/mutants/, by name.
std::vector<std::string> mutant_names() {
    std::vector<std::string> names;
    for (const fs::path& p : files_with_extension(mutants_source_dir(), ".patch")) names.push_back(p.stem().string());
    return names;
}

/// One scenario's entry in results.json.
struct ScenarioVerdict {
    std::string name;
    std::string verdict;  ///< "pass", "fail" or "firmware"
    std::string message;
};

struct SuiteRun {
    ProcessResult process;
    std::vector<ScenarioVerdict> verdicts;
};

/// Runs every shipped scenario, on `firmware` if given, and reads results.json.
SuiteRun run_shipped_scenarios(const std::optional<fs::path>& firmware) {
    TempDir dir;
    const fs::path out = dir / "results";
    std::string cmd = sh_quote(cli_path().string()) + " scenario";
    for (const fs::path& yaml : files_with_extension(source_dir() / "tests" / "scenarios", ".yaml")) {
        cmd += " " + sh_quote(yaml.string());
    }
    cmd += " -j2 --out " + sh_quote(out.string());
    if (firmware) cmd += " --firmware " + sh_quote(firmware->string());
    SuiteRun run;
    run.process = run_command(cmd);
    const std::string text = read_text(out / "results.json");
    if (text.empty()) return run;
    const json results = json::parse(text);  // named: a range-for over a temporary's member dangles
    for (const json& s : results.at("scenarios")) {
        run.verdicts.push_back({s.at("name").get<std::string>(), s.at("verdict").get<std::string>(),
                                s.at("message").get<std::string>()});
    }
    return run;
}

std::string describe(const SuiteRun& run) {
    return "exit " + std::to_string(run.process.exit_code) + "\nstdout:\n" + run.process.out + "stderr:\n" +
           run.process.err;
}

TEST(MutationCheck, EveryRequiredVariantHasAPatch) {
    const std::vector<std::string> names = mutant_names();
    for (const std::string& v : kRequiredVariants) {
        EXPECT_NE(std::find(names.begin(), names.end(), v), names.end()) << "no tests/mutants/" << v << ".patch";
    }
}

TEST(MutationCheck, ReferencePassesEveryShippedScenario) {
    const SuiteRun run = run_shipped_scenarios(std::nullopt);
    EXPECT_EQ(run.process.exit_code, 0) << describe(run);
    ASSERT_FALSE(run.verdicts.empty()) << describe(run);
    for (const ScenarioVerdict& v : run.verdicts) EXPECT_EQ(v.verdict, "pass") << v.name << ": " << v.message;
}

class MutantTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MutantTest, FailsAtLeastOneShippedScenario) {
    const std::string& name = GetParam();
    const fs::path elf = mutant_elf(name);
    ASSERT_TRUE(fs::exists(elf)) << elf << " is not built (target ddmr_mutants)";
    const SuiteRun run = run_shipped_scenarios(elf);

    // 1: a check failed; 3: the firmware crashed or timed out. Not 2 (input error).
    EXPECT_TRUE(run.process.exit_code == 1 || run.process.exit_code == 3) << describe(run);
    std::vector<ScenarioVerdict> caught;
    std::copy_if(run.verdicts.begin(), run.verdicts.end(), std::back_inserter(caught),
                 [](const ScenarioVerdict& v) { return v.verdict == "fail" || v.verdict == "firmware"; });
    EXPECT_FALSE(caught.empty()) << "mutant " << name << " passed every shipped scenario\n" << describe(run);

    std::printf("mutant %s: caught by %zu of %zu scenario(s)\n", name.c_str(), caught.size(), run.verdicts.size());
    for (const ScenarioVerdict& v : caught) {
        std::printf("  %-20s %-8s %s\n", v.name.c_str(), v.verdict.c_str(), v.message.c_str());
    }
}

INSTANTIATE_TEST_SUITE_P(Mutants, MutantTest, ::testing::ValuesIn(mutant_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace ddmr::test
