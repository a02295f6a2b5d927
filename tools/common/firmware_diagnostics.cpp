#include "common/firmware_diagnostics.hpp"

#include <cstdio>

namespace ddmr::tools {
using nlohmann::json;

hil::ZeroCallReport scan_zero_calls(const hil::ElfImage& elf, bool warn) {
    hil::ZeroCallReport report = hil::find_zero_calls(elf);
    if (warn) {
        for (const std::string& line : hil::describe_zero_calls(report)) {
            std::fprintf(stderr, "ddmr-hil: warning: firmware %s: %s\n", elf.path().c_str(), line.c_str());
        }
    }
    return report;
}

json zero_calls_json(const hil::ZeroCallReport& report) {
    json calls = json::array();
    for (const hil::ZeroCall& c : report.calls) {
        calls.push_back({{"pc", c.pc},
                         {"instruction", c.instruction},
                         {"function", c.function.empty() ? json(nullptr) : json(c.function)}});
    }
    return {{"calls", calls}, {"unresolved_weak", report.unresolved_weak}};
}

json unasked_resets_json(const hil::ResetMonitor& monitor) {
    if (!monitor.watching()) return nullptr;
    const auto& first = monitor.first();
    return {{"count", monitor.count()},
            {"first", first ? json{{"cycle", first->cycle}, {"sp", first->sp}, {"from", first->from}} : json(nullptr)}};
}

}  // namespace ddmr::tools
