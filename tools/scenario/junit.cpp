#include "scenario/junit.hpp"

#include <fmt/format.h>
#include <pugixml.hpp>

#include <sstream>

namespace ddmr::tools::scenario {

std::string junit_xml(const std::string& suite_name, const std::vector<ScenarioResult>& results) {
    pugi::xml_document doc;
    auto decl = doc.append_child(pugi::node_declaration);
    decl.append_attribute("version") = "1.0";
    decl.append_attribute("encoding") = "UTF-8";
    auto suites = doc.append_child("testsuites");
    auto suite = suites.append_child("testsuite");
    int failures = 0, errors = 0;
    double total_s = 0.0;
    for (const auto& r : results) {
        failures += r.verdict == Verdict::kFail ? 1 : 0;
        errors += r.verdict == Verdict::kFirmware ? 1 : 0;
        total_s += r.wall_seconds;
    }
    for (auto node : {suites, suite}) {
        node.append_attribute("name") = suite_name.c_str();
        node.append_attribute("tests") = static_cast<unsigned>(results.size());
        node.append_attribute("failures") = failures;
        node.append_attribute("errors") = errors;
        node.append_attribute("time") = fmt::format("{:.3f}", total_s).c_str();
    }
    for (const auto& r : results) {
        auto tc = suite.append_child("testcase");
        tc.append_attribute("name") = r.name.c_str();
        tc.append_attribute("classname") = fmt::format("scenario.{}", r.file.stem().string()).c_str();
        tc.append_attribute("file") = r.file.string().c_str();
        tc.append_attribute("time") = fmt::format("{:.3f}", r.wall_seconds).c_str();
        std::ostringstream log;
        for (const auto& s : r.steps) {
            log << fmt::format("line {:>3} t={:>10.6f} s {:<4} {}{}{}\n", s.line,
                               r.clock_hz == 0 ? 0.0 : static_cast<double>(s.cycle) / r.clock_hz,
                               s.passed ? "ok" : "FAIL", s.text, s.message.empty() ? "" : "  -- ", s.message);
        }
        if (r.verdict != Verdict::kPass) {
            auto f = tc.append_child(r.verdict == Verdict::kFail ? "failure" : "error");
            f.append_attribute("message") = r.message.c_str();
            f.append_attribute("type") = r.verdict == Verdict::kFail ? "check" : "firmware";
            f.append_child(pugi::node_pcdata).set_value(r.message.c_str());
        }
        tc.append_child("system-out").append_child(pugi::node_pcdata).set_value(log.str().c_str());
    }
    std::ostringstream out;
    doc.save(out, "  ", pugi::format_default, pugi::encoding_utf8);
    return out.str();
}

}  // namespace ddmr::tools::scenario
