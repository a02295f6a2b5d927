#include "calibrate/robot_log.hpp"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ddmr::calibrate {
namespace {

/// The sketch divides each EEPROM byte by 250.0 and prints 3 decimals.
constexpr double kCountsPerMetre = 250.0;
/// A printed value is b / 250 rounded to 3 decimals: within 0.0005 m, i.e.
/// 0.125 counts, of a whole count.
constexpr double kByteTolerance = 0.13;

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) s.remove_suffix(1);
    return s;
}

/// The whole of `s` (spaces around aside) as a T, or nullopt.
template <class T>
std::optional<T> parse_whole(std::string_view s) {
    s = trim(s);
    T v{};
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
    return v;
}

std::optional<double> number(std::string_view s) { return parse_whole<double>(s); }
std::optional<uint64_t> whole_number(std::string_view s) { return parse_whole<uint64_t>(s); }

/// "x , y" -> the two values, or nullopt if the line is not a pair of numbers.
std::optional<std::pair<double, double>> pair_line(std::string_view line) {
    const auto comma = line.find(',');
    if (comma == std::string_view::npos || line.find(',', comma + 1) != std::string_view::npos) return std::nullopt;
    const auto x = number(line.substr(0, comma));
    const auto y = number(line.substr(comma + 1));
    if (!x || !y) return std::nullopt;
    return std::pair{*x, *y};
}

/// "Gx,0.585,Gy,-0.112,t,12.000" -> key/value pairs; nullopt if not of that form.
std::optional<std::map<std::string, double>> field_line(std::string_view line) {
    std::map<std::string, double> out;
    std::vector<std::string_view> tokens;
    while (true) {
        const auto comma = line.find(',');
        tokens.push_back(trim(line.substr(0, comma)));
        if (comma == std::string_view::npos) break;
        line.remove_prefix(comma + 1);
    }
    if (tokens.size() < 2 || tokens.size() % 2 != 0) return std::nullopt;
    for (std::size_t i = 0; i < tokens.size(); i += 2) {
        const std::string_view key = tokens[i];
        if (key.empty() || std::isalpha(static_cast<unsigned char>(key.front())) == 0) return std::nullopt;
        // Arduino prints nan, inf and ovf for values a float cannot show.
        const auto v = number(tokens[i + 1]);
        const bool special = tokens[i + 1] == "nan" || tokens[i + 1] == "inf" || tokens[i + 1] == "-inf" ||
                             tokens[i + 1] == "ovf";
        if (!v && !special) return std::nullopt;
        out[std::string(key)] = v.value_or(std::nan(""));
    }
    return out;
}

/// The end of the dump. The sketch prints j = 0, 2, ..., addr: addr / 2 + 1
/// lines, the last the byte at addr, which the run never wrote (not a
/// sample). With addr printed, a dump that lacks only that line (a copy from
/// a serial monitor, a printed table) is read with a warning; one that lacks
/// more is cut and refused. Without addr the last line is taken as the
/// unwritten one.
void finish_dump(RobotLog& log) {
    const std::size_t lines = log.samples.size();
    const bool lacks_last = log.addr && lines == *log.addr / 2;
    if (lines < (lacks_last ? 2U : 3U)) {
        throw std::runtime_error(fmt::format("{}: the EEPROM dump has {} line(s) 'x , y' after END; at least 3 (2 "
                                             "logged samples and the unwritten byte at addr) are needed to calibrate",
                                             log.source, lines));
    }
    if (log.addr && !lacks_last && *log.addr / 2 + 1 != lines) {
        throw std::runtime_error(fmt::format("{}: addr {} promises {} dump lines, the file has {} (a cut log? only the "
                                             "last, the unwritten byte at addr, may be missing)",
                                             log.source, *log.addr, *log.addr / 2 + 1, lines));
    }
    if (lacks_last) {
        log.warnings.push_back(fmt::format("{}: addr {} promises {} dump lines, the file has {}: read as the dump "
                                           "without its last line (the byte at addr, which the run never wrote), "
                                           "{} logged samples",
                                           log.source, *log.addr, lines + 1, lines, lines));
        return;
    }
    log.unwritten = log.samples.back();
    log.samples.pop_back();
}

}  // namespace

RobotLog parse_robot_log(std::string_view text, const std::string& source) {
    RobotLog log;
    log.source = source;
    const auto fail = [&](int line, const std::string& what) {
        throw std::runtime_error(fmt::format("{}:{}: {}", source, line, what));
    };
    enum class Stage { kBeforeEnd, kCount1, kCount2, kReport, kDump, kAfterDump };
    Stage stage = Stage::kBeforeEnd;
    int end_line = 0;
    int line_no = 0;
    std::size_t at = 0;
    while (at <= text.size()) {
        const std::size_t nl = text.find('\n', at);
        const std::string_view raw = text.substr(at, nl == std::string_view::npos ? std::string_view::npos : nl - at);
        at = nl == std::string_view::npos ? text.size() + 1 : nl + 1;
        ++line_no;
        const std::string_view line = trim(raw);
        if (line.empty()) continue;
        if (line == "END") {
            if (stage != Stage::kBeforeEnd) {
                fail(line_no, fmt::format("a second END (the first is on line {}): the file holds more than one "
                                          "run; give each run its own file",
                                          end_line));
            }
            stage = Stage::kCount1;
            end_line = line_no;
            continue;
        }
        switch (stage) {
            case Stage::kBeforeEnd:
                if (line == "0.6m") log.case_number = 1;
                if (line == "0.4m") log.case_number = 2;
                break;
            case Stage::kCount1:
            case Stage::kCount2: {
                const auto n = whole_number(line);
                const char* name = stage == Stage::kCount1 ? "Count1" : "Count2";
                if (!n) fail(line_no, fmt::format("expected {} (a whole number of encoder edges) after END, got '{}'", name, line));
                (stage == Stage::kCount1 ? log.count1 : log.count2) = *n;
                stage = stage == Stage::kCount1 ? Stage::kCount2 : Stage::kReport;
                break;
            }
            case Stage::kReport:
                if (const auto f = field_line(line)) {
                    for (const auto& [k, v] : *f) log.fields[k] = v;
                    break;
                }
                if (const auto a = whole_number(line)) {
                    if (log.addr) fail(line_no, fmt::format("a second addr line '{}' (addr was {})", line, *log.addr));
                    log.addr = *a;
                    break;
                }
                if (pair_line(line)) {
                    stage = Stage::kDump;
                } else {
                    fail(line_no, fmt::format("'{}' is neither a report line (Key,value,...), addr, nor a dump line "
                                              "'x , y'",
                                              line));
                }
                [[fallthrough]];
            case Stage::kDump: {
                const auto p = pair_line(line);
                if (!p) {
                    stage = Stage::kAfterDump;
                    break;
                }
                LoggedSample s;
                s.line = line_no;
                for (const auto& [value, byte] : {std::pair{p->first, &s.x_byte}, std::pair{p->second, &s.y_byte}}) {
                    const double counts = value * kCountsPerMetre;
                    const double b = std::round(counts);
                    if (!(b >= 0.0 && b <= 255.0) || std::fabs(counts - b) > kByteTolerance) {
                        fail(line_no, fmt::format("'{}': {} is not an EEPROM byte over 250 (0, 0.004, ..., 1.020)", line,
                                                  value));
                    }
                    *byte = static_cast<uint8_t>(b);
                }
                log.samples.push_back(s);
                break;
            }
            case Stage::kAfterDump:
                if (pair_line(line)) {
                    fail(line_no, fmt::format("dump line '{}' after the dump ended: the dump must be contiguous", line));
                }
                break;
        }
    }
    if (stage == Stage::kBeforeEnd) {
        throw std::runtime_error(fmt::format("{}: no END line: not the end of a run of the reference sketch "
                                             "(END, Count1, Count2, then the EEPROM dump)",
                                             source));
    }
    if (stage == Stage::kCount1 || stage == Stage::kCount2) {
        throw std::runtime_error(fmt::format("{}:{}: the file ends before {} (after END)", source, end_line,
                                             stage == Stage::kCount1 ? "Count1" : "Count2"));
    }
    finish_dump(log);
    return log;
}

RobotLog read_robot_log(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error(fmt::format("{}: cannot read the log (missing or unreadable)", path.string()));
    std::ostringstream buffer;
    buffer << in.rdbuf();
    return parse_robot_log(buffer.str(), path.string());
}

}  // namespace ddmr::calibrate
