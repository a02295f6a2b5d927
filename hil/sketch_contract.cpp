#include "hil/sketch_contract.hpp"

#include <fmt/format.h>

#include <regex>
#include <stdexcept>

#include "hil/mcu.hpp"
#include "hil/yaml_reader.hpp"

namespace ddmr::hil {
namespace {

constexpr const char* kCasePlaceholder = "{case}";

/// "2s", "500ms", "250us" -> seconds (a number without a unit is refused).
double duration_s(const YamlReader& r, const YAML::Node& n, const std::string& key) {
    const std::string t = r.text(n, key);
    for (const auto& [unit, scale] : {std::pair<const char*, double>{"ms", 1e-3}, {"us", 1e-6}, {"s", 1.0}}) {
        const std::string u = unit;
        if (t.size() > u.size() && t.compare(t.size() - u.size(), u.size(), u) == 0) {
            YAML::Node number(t.substr(0, t.size() - u.size()));
            return r.number(number, key, 0.0, 1e6) * scale;
        }
    }
    r.fail(n, key, fmt::format("'{}' needs a unit: s, ms or us (e.g. 5s)", t));
}

}  // namespace

const char* to_string(ReportFormat f) {
    switch (f) {
        case ReportFormat::kDdmrTracking: return "ddmr-tracking";
        case ReportFormat::kFields: return "fields";
        case ReportFormat::kNone: break;
    }
    return "none";
}

std::string SketchContract::start_text(int test_case) const {
    if (!start) return "";
    std::string text = start->send;
    const auto at = text.find(kCasePlaceholder);
    if (at == std::string::npos) return text;
    bool known = false;
    for (const int c : start->cases) known = known || c == test_case;
    if (!known) {
        std::string list;
        for (const int c : start->cases) list += (list.empty() ? "" : ", ") + std::to_string(c);
        throw std::invalid_argument(
            fmt::format("--case {}: the sketch contract {} knows cases {}", test_case, source, list));
    }
    text.replace(at, std::string(kCasePlaceholder).size(), std::to_string(test_case));
    return text;
}

SketchContract load_sketch_contract(const std::filesystem::path& path) {
    const YAML::Node root = YamlReader::load(path, "the sketch contract");
    const YamlReader r{path.string()};
    SketchContract c;
    c.source = path.string();
    if (root.IsNull()) return c;  // an empty contract: nothing special
    r.mapping(root, "(top)");
    r.only_keys(root, "", {"start", "complete", "report", "pose", "loop", "trace", "eeprom-log"});
    if (const YAML::Node n = root["start"]) {
        r.mapping(n, "start");
        r.only_keys(n, "start", {"send", "cases", "after-return", "at", "after-text"});
        ContractStart s;
        if (!n["send"]) r.fail(n, "start.send", "missing: the text to send the firmware");
        s.send = r.text(n["send"], "start.send");
        int whens = 0;
        if (n["after-return"]) s.after_return = r.text(n["after-return"], "start.after-return"), ++whens;
        if (n["at"]) s.at_s = duration_s(r, n["at"], "start.at"), ++whens;
        if (n["after-text"]) s.after_text = r.text(n["after-text"], "start.after-text"), ++whens;
        if (whens != 1) r.fail(n, "start", "give exactly one of after-return, at, after-text");
        const bool has_case = s.send.find(kCasePlaceholder) != std::string::npos;
        if (n["cases"]) {
            const YAML::Node cases = n["cases"];
            if (!cases.IsSequence() || cases.size() == 0) r.fail(cases, "start.cases", "expected a list of case numbers");
            for (std::size_t i = 0; i < cases.size(); ++i) {
                s.cases.push_back(static_cast<int>(r.integer(cases[i], fmt::format("start.cases[{}]", i), 0, 255)));
            }
            if (!has_case) r.fail(cases, "start.cases", "the send text has no {case} to put them in");
            s.default_case = s.cases.front();
        } else if (has_case) {
            r.fail(n["send"], "start.send", "{case} needs a cases list (e.g. cases: [1, 2])");
        }
        c.start = s;
    }
    if (const YAML::Node n = root["report"]) {
        if (n.IsMap()) {  // named fields: {name: "regex with (a number)", ...}
            r.only_keys(n, "report", {"fields"});
            if (!n["fields"] || !n["fields"].IsMap() || n["fields"].size() == 0) {
                r.fail(n, "report.fields", "expected a mapping of field names to patterns");
            }
            for (const auto& kv : n["fields"]) {
                const std::string name = kv.first.Scalar();
                const std::string key = "report.fields." + name;
                const std::string pattern = r.text(kv.second, key);
                try {
                    const std::regex re(pattern);
                    if (re.mark_count() < 1) r.fail(kv.second, key, "the pattern needs a (group) around the number");
                } catch (const std::regex_error& e) {
                    r.fail(kv.second, key, fmt::format("'{}' is not a regular expression: {}", pattern, e.what()));
                }
                c.report_fields.push_back(ReportField{name, pattern});
            }
            c.report = ReportFormat::kFields;
        } else {
            const std::string f = r.text(n, "report");
            if (f == "ddmr-tracking") {
                c.report = ReportFormat::kDdmrTracking;
            } else if (f != "none") {
                r.fail(n, "report", fmt::format("unknown report format '{}' (none, ddmr-tracking, or fields: {{...}})", f));
            }
        }
    }
    if (const YAML::Node n = root["complete"]) {
        r.mapping(n, "complete");
        r.only_keys(n, "complete", {"text", "lines-after", "report"});
        ContractComplete done;
        if (n["text"]) done.text = r.text(n["text"], "complete.text");
        if (n["lines-after"]) {
            if (!done.text) r.fail(n["lines-after"], "complete.lines-after", "needs complete.text");
            done.lines_after = static_cast<int>(r.integer(n["lines-after"], "complete.lines-after", 0, 100000));
        }
        if (n["report"]) {
            done.report = r.boolean(n["report"], "complete.report");
            if (done.report && c.report != ReportFormat::kDdmrTracking) {
                r.fail(n["report"], "complete.report",
                       "needs a report format that knows its end (report: ddmr-tracking); fields: use complete.text");
            }
        }
        if (!done.text && !done.report) r.fail(n, "complete", "give text (and lines-after) or report: true");
        if (done.text && done.report) r.fail(n, "complete", "give text or report: true, not both");
        c.complete = done;
    }
    if (const YAML::Node n = root["pose"]) {
        r.mapping(n, "pose");
        r.only_keys(n, "pose", {"x", "y", "theta", "at-text"});
        ContractPose p;
        for (const auto& [key, field] : {std::pair<const char*, std::string*>{"x", &p.x}, {"y", &p.y}, {"theta", &p.theta}}) {
            if (!n[key]) r.fail(n, fmt::format("pose.{}", key), "missing: the float global that holds it");
            *field = r.text(n[key], fmt::format("pose.{}", key));
        }
        if (n["at-text"]) p.at_text = r.text(n["at-text"], "pose.at-text");
        c.pose = p;
    }
    if (const YAML::Node n = root["loop"]) {
        r.mapping(n, "loop");
        r.only_keys(n, "loop", {"marker", "function"});
        if (n["marker"]) c.loop.marker = r.text(n["marker"], "loop.marker");
        if (n["function"]) c.loop.function = r.text(n["function"], "loop.function");
    }
    if (const YAML::Node n = root["trace"]) c.trace = r.text_list(n, "trace");
    if (c.loop.marker && c.trace.empty()) c.trace.push_back(*c.loop.marker);
    if (const YAML::Node n = root["eeprom-log"]) {
        r.mapping(n, "eeprom-log");
        r.only_keys(n, "eeprom-log",
                    {"x-address", "y-address", "stride", "counts-per-metre", "signed", "unwrap", "sample-period"});
        EepromLogLayout l;
        const auto eeprom_end = static_cast<long>(kMaxEepromBytes) - 1;  // the board's is checked at run time
        if (!n["x-address"] || !n["y-address"]) r.fail(n, "eeprom-log", "give x-address and y-address");
        l.x_address = static_cast<int>(r.integer(n["x-address"], "eeprom-log.x-address", 0, eeprom_end));
        l.y_address = static_cast<int>(r.integer(n["y-address"], "eeprom-log.y-address", 0, eeprom_end));
        if (n["stride"]) l.stride = static_cast<int>(r.integer(n["stride"], "eeprom-log.stride", 1, eeprom_end));
        if (n["counts-per-metre"]) {
            l.counts_per_metre = r.number(n["counts-per-metre"], "eeprom-log.counts-per-metre", 1e-6, 1e9);
        }
        if (n["signed"]) l.is_signed = r.boolean(n["signed"], "eeprom-log.signed");
        if (n["unwrap"]) l.unwrap = r.boolean(n["unwrap"], "eeprom-log.unwrap");
        if (!l.is_signed && n["unwrap"] && l.unwrap) {
            r.fail(n["unwrap"], "eeprom-log.unwrap", "unwrapping starts from a signed first sample: not with signed: false");
        }
        if (!l.is_signed) l.unwrap = false;
        if (n["sample-period"]) l.sample_period_s = duration_s(r, n["sample-period"], "eeprom-log.sample-period");
        if (l.max_samples(static_cast<int>(kMaxEepromBytes)) == 0) {
            r.fail(n, "eeprom-log", "the x and y series leave no room for a sample");
        }
        c.eeprom_log = l;
    }
    return c;
}

}  // namespace ddmr::hil
