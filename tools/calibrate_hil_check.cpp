#include "calibrate_hil_check.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

#include "calibrate/log_objective.hpp"
#include "firmware_run.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
namespace cal = ddmr::calibrate;

/// The HIL's own dump against a log: the distance between the decoded tracks.
struct HilMatch {
    double rms_m = 0.0, max_m = 0.0, endpoint_m = 0.0;
    std::size_t samples = 0;
};

HilMatch match(const cal::RobotLog& hil, const cal::RobotLog& log) {
    const auto a = cal::logged_positions(hil);
    const auto b = cal::logged_positions(log);
    HilMatch m;
    m.samples = std::min(a.size(), b.size());
    double sq = 0.0;
    for (std::size_t k = 0; k < m.samples; ++k) {
        const double d = std::hypot(a[k].first - b[k].first, a[k].second - b[k].second);
        sq += d * d;
        m.max_m = std::max(m.max_m, d);
        m.endpoint_m = d;
    }
    if (m.samples > 0) m.rms_m = std::sqrt(sq / static_cast<double>(m.samples));
    return m;
}

}  // namespace

HilConfirmation confirm_in_hil(const std::optional<std::string>& firmware, const std::vector<cal::RobotLog>& all,
                               int case_number, const fs::path& out,
                               const std::function<void(const std::string&)>& say) {
    HilConfirmation c;
    if (!firmware) {
        c.json = nullptr;
        c.md = "Not run (`--no-hil`).\n";
    } else {
        say("confirming in the HIL (the real firmware on the fitted plant)");
        FirmwareRunOptions fo;
        fo.firmware = *firmware;
        fo.contract = DDMR_DEFAULT_CONTRACT;
        fo.test_case = case_number;
        fo.case_given = true;
        fo.reference_protocol_required = true;
        fo.plant_file = out / "plant.yaml";
        fo.out_dir = out / "hil";
        FirmwareRunResult run;
        std::string failure;
        std::optional<cal::RobotLog> hil_read;
        try {
            run = run_firmware(fo);
            if (run.exit != RunExit::kReportComplete) {
                failure = run.message;
            } else {
                hil_read = cal::read_robot_log(out / "hil" / "uart.txt");
            }
        } catch (const std::exception& e) {
            failure = e.what();  // the fit's outputs are still written below
        }
        nlohmann::json h = {{"exit", failure.empty() ? to_string(run.exit) : "error"}, {"folder", "hil"}};
        if (!failure.empty()) {
            run.message = failure;
            c.exit_code = kExitFirmware;
            h["message"] = run.message;
            c.md = fmt::format("The HIL run did not complete: {}\n", run.message);
            std::fprintf(stderr, "ddmr-hil calibrate: the HIL confirmation failed: %s\n", run.message.c_str());
        } else {
            const cal::RobotLog& hil_log = *hil_read;
            nlohmann::json per = nlohmann::json::array();
            std::vector<std::string> hil_lines;
            c.md = "| log | RMS [mm] | max [mm] | end [mm] | Count1 HIL / log | Count2 HIL / log |\n|---|---|---|---|---|---|\n";
            for (const cal::RobotLog& l : all) {
                const HilMatch m = match(hil_log, l);
                hil_lines.push_back(fmt::format("{:.1f} mm RMS to {}", m.rms_m * 1e3, l.source));
                per.push_back({{"log", l.source}, {"rms_m", m.rms_m}, {"max_m", m.max_m}, {"endpoint_m", m.endpoint_m},
                               {"samples", m.samples}});
                c.md += fmt::format("| {} | {:.1f} | {:.1f} | {:.1f} | {} / {} | {} / {} |\n", l.source, m.rms_m * 1e3,
                                      m.max_m * 1e3, m.endpoint_m * 1e3, hil_log.count1, l.count1, hil_log.count2,
                                      l.count2);
            }
            c.summary = fmt::format("  HIL (the real firmware on the fitted plant): {}", fmt::join(hil_lines, "; "));
            h["count1"] = hil_log.count1;
            h["count2"] = hil_log.count2;
            h["logs"] = per;
        }
        c.json = h;
    }
    return c;
}

}  // namespace ddmr::tools
