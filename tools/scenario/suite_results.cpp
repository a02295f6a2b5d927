#include "scenario/suite_results.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <regex>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "exit_codes.hpp"
#include "scenario/junit.hpp"

namespace ddmr::tools::scenario {
namespace fs = std::filesystem;
using nlohmann::json;

Shard parse_shard(const std::string& text) {
    static const std::regex re(R"(^([0-9]{1,6})/([0-9]{1,6})$)");
    std::smatch m;
    if (!std::regex_match(text, m, re)) {
        throw std::invalid_argument(fmt::format("--shard '{}': expected I/N, e.g. 2/4", text));
    }
    Shard s{static_cast<unsigned>(std::stoul(m[1].str())), static_cast<unsigned>(std::stoul(m[2].str()))};
    if (s.count == 0 || s.index == 0 || s.index > s.count) {
        throw std::invalid_argument(fmt::format("--shard '{}': I must be in 1..N and N >= 1", text));
    }
    return s;
}

ScenarioResult read_scenario_result(const fs::path& dir) {
    const fs::path p = dir / "result.json";
    std::ifstream in(p);
    if (!in) throw std::runtime_error(p.string() + ": missing (not a scenario result folder?)");
    json j;
    try {
        j = json::parse(in);
        ScenarioResult r;
        r.name = j.at("name").get<std::string>();
        r.file = j.at("file").get<std::string>();
        const std::string v = j.at("verdict").get<std::string>();
        r.verdict = v == "pass" ? Verdict::kPass : v == "fail" ? Verdict::kFail : Verdict::kFirmware;
        r.message = j.at("message").get<std::string>();
        r.cycles = j.at("cycles").get<uint64_t>();
        r.clock_hz = j.at("clock_hz").get<uint32_t>();
        r.sim_seconds = j.at("sim_seconds").get<double>();
        for (const auto& st : j.at("steps")) {
            r.steps.push_back({st.at("line").get<int>(), st.at("kind").get<std::string>(),
                               st.at("step").get<std::string>(), st.at("passed").get<bool>(),
                               st.at("cycle").get<uint64_t>(), st.at("message").get<std::string>()});
        }
        return r;
    } catch (const json::exception& e) {
        throw std::runtime_error(p.string() + ": malformed: " + e.what());
    }
}

json suite_results_json(const std::vector<ScenarioResult>& results) {
    json list = json::array();
    for (const auto& r : results) {
        list.push_back({{"name", r.name}, {"file", r.file.string()}, {"verdict", to_string(r.verdict)},
                        {"message", r.message}, {"sim_seconds", r.sim_seconds}});
    }
    const auto passed = std::count_if(results.begin(), results.end(),
                                      [](const ScenarioResult& r) { return r.verdict == Verdict::kPass; });
    const auto failed = std::count_if(results.begin(), results.end(),
                                      [](const ScenarioResult& r) { return r.verdict == Verdict::kFail; });
    const auto errors = std::count_if(results.begin(), results.end(),
                                      [](const ScenarioResult& r) { return r.verdict == Verdict::kFirmware; });
    return json{{"scenarios", list}, {"passed", passed}, {"failed", failed}, {"errors", errors}, {"total", results.size()}};
}

int suite_exit_code(const std::vector<ScenarioResult>& results) {
    int exit = kExitOk;
    for (const auto& r : results) {
        if (r.verdict == Verdict::kFirmware) return kExitFirmware;
        if (r.verdict == Verdict::kFail) exit = kExitCheckFailed;
    }
    return exit;
}

void print_verdicts(const std::vector<ScenarioResult>& results) {
    for (const auto& r : results) {
        const char* tag = r.verdict == Verdict::kPass ? "PASS" : r.verdict == Verdict::kFail ? "FAIL" : "ERROR";
        const std::string wall = r.wall_seconds > 0 ? fmt::format(", {:.1f} s wall", r.wall_seconds) : "";
        std::printf("%-5s %s (%s: %.3f s simulated%s)\n", tag, r.name.c_str(), r.file.string().c_str(), r.sim_seconds,
                    wall.c_str());
        if (r.verdict != Verdict::kPass) std::printf("      %s\n", r.message.c_str());
    }
    const auto passed = std::count_if(results.begin(), results.end(),
                                      [](const ScenarioResult& r) { return r.verdict == Verdict::kPass; });
    std::printf("%zd of %zu scenario%s passed\n", passed, results.size(), results.size() == 1 ? "" : "s");
}

int finish_suite(const std::vector<ScenarioResult>& results, const fs::path& out_dir, const fs::path& junit_path) {
    print_verdicts(results);
    write_file_atomic(out_dir / "results.json", suite_results_json(results).dump(2) + "\n");
    if (!junit_path.empty()) write_file_atomic(junit_path, junit_xml("ddmr-hil scenarios", results));
    return suite_exit_code(results);
}

}  // namespace ddmr::tools::scenario
