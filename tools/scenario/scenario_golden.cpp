#include "scenario/scenario_golden.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <regex>

#include "common/atomic_file.hpp"

namespace ddmr::tools::scenario {

void apply_golden(const Scenario& s_, const std::vector<Golden>& golden_, ScenarioResult& r) {
    if (golden_.empty()) return;
    if (r.verdict != Verdict::kPass) {
        r.message += fmt::format(" (--update-golden: nothing recorded, the run did not pass)");
        return;
    }
    // The scenario file: each pose step's own lines, from its line to the next step's.
    std::string text;
    {
        std::ifstream in(s_.file, std::ios::binary);
        text.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    std::vector<std::string> lines;
    for (std::size_t a = 0; a <= text.size();) {
        const std::size_t b = text.find('\n', a);
        lines.push_back(text.substr(a, b == std::string::npos ? std::string::npos : b - a));
        if (b == std::string::npos) break;
        a = b + 1;
    }
    std::vector<std::string> recorded;
    bool yaml_changed = false;
    for (const Golden& g : golden_) {
        if (g.file) {
            write_file_atomic(*g.file, g.bytes);
            recorded.push_back(g.file->filename().string());
            continue;
        }
        int end_line = static_cast<int>(lines.size()) + 1;
        for (const Step& st : s_.steps) {
            if (st.line > g.line) end_line = std::min(end_line, st.line);
        }
        const auto set = [&](const char* key, double value) {
            const std::regex re(std::string("(\\b") + key + ":\\s*)[-+0-9.eE]+");
            for (int l = g.line; l < end_line && l <= static_cast<int>(lines.size()); ++l) {
                std::string& line = lines[static_cast<std::size_t>(l - 1)];
                std::smatch m;
                if (std::regex_search(line, m, re)) {
                    line = m.prefix().str() + m[1].str() + fmt::format("{:.4f}", value) + m.suffix().str();
                    return;
                }
            }
        };
        set("x_m", g.pose->x_m);
        set("y_m", g.pose->y_m);
        set("theta_rad", g.pose->theta_rad);  // only where the step gives one
        yaml_changed = true;
        recorded.push_back(fmt::format("the pose at line {}", g.line));
    }
    if (yaml_changed) {
        std::string out;
        for (std::size_t l = 0; l < lines.size(); ++l) out += lines[l] + (l + 1 < lines.size() ? "\n" : "");
        write_file_atomic(s_.file, out);
    }
    r.message = fmt::format("--update-golden: recorded {}", fmt::join(recorded, ", "));
}

}  // namespace ddmr::tools::scenario
