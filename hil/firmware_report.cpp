#include "hil/firmware_report.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>

namespace ddmr::hil {
namespace {

/// Parses one number as Arduino's Print prints it ("1.234", "-0.5", "12",
/// "nan", "inf", "-inf", "ovf"). Returns nullopt if it is none of those.
std::optional<double> parse_number(std::string_view s) {
    while (!s.empty() && s.front() == ' ') s.remove_prefix(1);
    while (!s.empty() && s.back() == ' ') s.remove_suffix(1);
    if (s == "nan") return std::numeric_limits<double>::quiet_NaN();
    if (s == "inf" || s == "ovf") return std::numeric_limits<double>::infinity();
    if (s == "-inf" || s == "-ovf") return -std::numeric_limits<double>::infinity();
    if (s.empty()) return std::nullopt;
    const std::string str(s);
    char* end = nullptr;
    const double v = std::strtod(str.c_str(), &end);
    if (end != str.c_str() + str.size()) return std::nullopt;
    return v;
}

/// Splits "k1,v1,k2,v2,..." and checks the keys; fills `out` with the values.
bool parse_keyed(std::string_view line, std::initializer_list<const char*> keys,
                 std::initializer_list<std::optional<double>*> out) {
    std::vector<std::string_view> parts;
    std::size_t start = 0;
    for (;;) {
        const std::size_t comma = line.find(',', start);
        parts.push_back(line.substr(start, comma == std::string_view::npos ? std::string_view::npos
                                                                           : comma - start));
        if (comma == std::string_view::npos) break;
        start = comma + 1;
    }
    if (parts.size() != 2 * keys.size()) return false;
    auto key = keys.begin();
    auto dst = out.begin();
    for (std::size_t i = 0; i < parts.size(); i += 2, ++key, ++dst) {
        if (parts[i] != *key) return false;
        const auto v = parse_number(parts[i + 1]);
        if (!v) return false;
        **dst = *v;
    }
    return true;
}

}  // namespace

void FirmwareReportParser::feed(std::string_view bytes) {
    for (const char c : bytes) {
        if (stage_ == Stage::kComplete || error_) return;
        if (c == '\n') {
            if (!partial_.empty() && partial_.back() == '\r') partial_.pop_back();
            ++line_number_;
            on_line(partial_);
            partial_.clear();
        } else {
            partial_.push_back(c);
        }
    }
}

void FirmwareReportParser::fail(const std::string& line, const char* expected) {
    error_ = "firmware report line " + std::to_string(line_number_) + " \"" + line +
             "\": expected " + expected;
}

void FirmwareReportParser::on_line(const std::string& line) {
    switch (stage_) {
        case Stage::kBanner:
            // Anything before the banner (boot chatter) is ignored.
            if (line == "0.6m" || line == "0.4m") {
                report_.banner = line;
                stage_ = Stage::kEnd;
            }
            return;
        case Stage::kEnd:
            if (line != "END") return fail(line, "END");
            report_.ended = true;
            stage_ = Stage::kCount1;
            return;
        case Stage::kCount1:
            if (!(report_.count1 = parse_number(line))) return fail(line, "Count1");
            stage_ = Stage::kCount2;
            return;
        case Stage::kCount2:
            if (!(report_.count2 = parse_number(line))) return fail(line, "Count2");
            stage_ = Stage::kGoal;
            return;
        case Stage::kGoal:
            if (!parse_keyed(line, {"Gx", "Gy", "t"}, {&report_.gx, &report_.gy, &report_.t})) {
                return fail(line, "Gx,<x>,Gy,<y>,t,<t>");
            }
            stage_ = Stage::kPdt;
            return;
        case Stage::kPdt:
            if (!parse_keyed(line, {"pdt1", "pdt2"}, {&report_.pdt1, &report_.pdt2})) {
                return fail(line, "pdt1,<w1>,pdt2,<w2>");
            }
            stage_ = Stage::kVel;
            return;
        case Stage::kVel:
            if (!parse_keyed(line, {"V", "W"}, {&report_.v, &report_.w})) {
                return fail(line, "V,<v>,W,<w>");
            }
            stage_ = Stage::kPose;
            return;
        case Stage::kPose:
            if (!parse_keyed(line, {"Ex", "Ey", "Thta"}, {&report_.ex, &report_.ey, &report_.theta})) {
                return fail(line, "Ex,<x>,Ey,<y>,Thta,<theta>");
            }
            stage_ = Stage::kErr;
            return;
        case Stage::kErr:
            if (!parse_keyed(line, {"ex", "ey", "exr"},
                             {&report_.errx, &report_.erry, &report_.errxr})) {
                return fail(line, "ex,<ex>,ey,<ey>,exr,<exr>");
            }
            stage_ = expects_eeprom_dump_ ? Stage::kAddr : Stage::kComplete;
            return;
        case Stage::kAddr: {
            report_.addr = parse_number(line);
            if (!report_.addr || !(*report_.addr >= 0) || *report_.addr > 1024 ||
                std::fmod(*report_.addr, 2.0) != 0.0) {
                return fail(line, "addr, an even number of bytes from 0 to 1024");
            }
            // for (int j = 0; j <= addr; j += 2): addr/2 + 1 pairs.
            pairs_expected_ = static_cast<std::size_t>(*report_.addr) / 2 + 1;
            stage_ = Stage::kPairs;
            return;
        }
        case Stage::kPairs: {
            const std::size_t sep = line.find(" , ");
            const auto x = sep == std::string::npos ? std::nullopt : parse_number(line.substr(0, sep));
            const auto y = sep == std::string::npos ? std::nullopt : parse_number(line.substr(sep + 3));
            if (!x || !y) return fail(line, "<x> , <y>");
            report_.eeprom_pairs.emplace_back(*x, *y);
            if (report_.eeprom_pairs.size() == pairs_expected_) stage_ = Stage::kComplete;
            return;
        }
        case Stage::kComplete:
            return;
    }
}

}  // namespace ddmr::hil
