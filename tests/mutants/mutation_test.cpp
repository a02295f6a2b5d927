// The mutation check of issue 7: the shipped scenarios (tests/scenarios/*.yaml)
// must catch real firmware regressions. The reference firmware passes every
// one of them; each mutant (tests/mutants/<name>.patch, built to
// build/mutants/<name>.elf) must fail exactly the scenarios named for it below
// (issue 32, item 7: a scenario that stops catching its mutant, or a mutant
// that starts failing a scenario it should pass, both show). Each run prints
// which scenarios caught the mutant and the one-line message they gave.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

/// The variants the requirements name (issue 7's six, issue 32's two timing
/// mutants); each must have its patch.
const std::vector<std::string> kRequiredVariants = {"kx_float",        "encoder_pins_swapped", "delay_5",
                                                    "no_eeprom_writes", "ky_sign_flipped",      "baud_19200",
                                                    "slow_encoder_isr", "loop_extra_compute"};

const std::set<std::string> kAllScenarios = {"case1_converges", "case2_converges", "eeprom_vs_sim", "encoder_drop",
                                             "isr_latency",     "loop_timing",     "push_recovery"};

/// The scenarios that catch each mutant, and why (tests/mutants/README.md
/// has each one's first failing line).
const std::map<std::string, std::set<std::string>>& expected_catchers() {
    static const std::map<std::string, std::set<std::string>> catchers = {
        // Closed-loop tracking hides the 10 % gain change by the end of the
        // circle; only the early samples of the EEPROM log differ by more
        // than their 4.1 mm tolerance.
        {"kx_float", {"eeprom_vs_sim"}},
        // Each counter counts the other wheel: the robot spins off the circle,
        // every pose and log check fails. isr_latency's bounds hold (the ISRs
        // are the same code), and loop_timing's too (the loop's work is the same).
        {"encoder_pins_swapped",
         {"case1_converges", "case2_converges", "eeprom_vs_sim", "encoder_drop", "push_recovery"}},
        // A 6 ms period: the loop timing and, with dt still 0.01 s, every
        // pose; the case ends after 7 s instead of 12, with other edge times:
        // an INT1 edge once waits for two handlers of ~100 cycles each
        // (isr_latency's 150-cycle bound).
        {"delay_5", kAllScenarios},
        // No log to compare; no iteration's compute holds a 3.3 ms EEPROM
        // write (loop_timing's 3.5-5 ms maximum). The robot and its ISRs do
        // as before.
        {"no_eeprom_writes", {"eeprom_vs_sim", "loop_timing"}},
        // The lateral error fed back with the wrong sign: the robot leaves
        // the circle, and its wheels turn less (fewer INT0 entries than
        // isr_latency's minimum); the loop's timing does not change.
        {"ky_sign_flipped",
         {"case1_converges", "case2_converges", "eeprom_vs_sim", "encoder_drop", "isr_latency", "push_recovery"}},
        // No case byte is ever read right: no scenario's case starts.
        {"baud_19200", kAllScenarios},
        // INT0 takes ~160 cycles instead of 101 (isr_latency's 120-cycle
        // bound). The 0.15 % of CPU it adds moves the path only
        // within the EEPROM log's quantization (eeprom_vs_sim's one count
        // per axis).
        {"slow_encoder_isr", {"isr_latency"}},
        // One iteration a second computes ~0.6 ms longer (loop_timing's
        // 1.3 ms bound without EEPROM writes); the mean period grows by
        // 0.06 %, the path only within the log's quantization.
        {"loop_extra_compute", {"loop_timing"}},
    };
    return catchers;
}

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

TEST(MutationCheck, EveryMutantNamesTheScenariosThatCatchIt) {
    std::set<std::string> shipped;
    for (const fs::path& yaml : files_with_extension(source_dir() / "tests" / "scenarios", ".yaml")) {
        shipped.insert(yaml.stem().string());
    }
    EXPECT_EQ(shipped, kAllScenarios) << "a shipped scenario was added or removed: name what catches each mutant";
    for (const std::string& name : mutant_names()) {
        const auto it = expected_catchers().find(name);
        ASSERT_NE(it, expected_catchers().end()) << "tests/mutants/" << name << ".patch: name the scenarios it fails";
        EXPECT_FALSE(it->second.empty()) << name;
        for (const std::string& s : it->second) EXPECT_EQ(kAllScenarios.count(s), 1U) << name << ": " << s;
    }
}

TEST(MutationCheck, ReferencePassesEveryShippedScenario) {
    const SuiteRun run = run_shipped_scenarios(std::nullopt);
    EXPECT_EQ(run.process.exit_code, 0) << describe(run);
    ASSERT_FALSE(run.verdicts.empty()) << describe(run);
    for (const ScenarioVerdict& v : run.verdicts) EXPECT_EQ(v.verdict, "pass") << v.name << ": " << v.message;
}

class MutantTest : public ::testing::TestWithParam<std::string> {};

TEST_P(MutantTest, FailsExactlyTheScenariosNamedForIt) {
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
    EXPECT_EQ(run.verdicts.size(), kAllScenarios.size()) << describe(run);
    std::set<std::string> caught_by;
    for (const ScenarioVerdict& v : caught) caught_by.insert(v.name);
    const auto expected = expected_catchers().find(name);
    ASSERT_NE(expected, expected_catchers().end()) << name;
    EXPECT_EQ(caught_by, expected->second) << "mutant " << name << "\n" << describe(run);

    std::printf("mutant %s: caught by %zu of %zu scenario(s)\n", name.c_str(), caught.size(), run.verdicts.size());
    for (const ScenarioVerdict& v : caught) {
        std::printf("  %-20s %-8s %s\n", v.name.c_str(), v.verdict.c_str(), v.message.c_str());
    }
}

INSTANTIATE_TEST_SUITE_P(Mutants, MutantTest, ::testing::ValuesIn(mutant_names()),
                         [](const ::testing::TestParamInfo<std::string>& p) { return p.param; });

}  // namespace
}  // namespace ddmr::test
