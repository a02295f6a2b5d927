// The scenario steps that check what a whole run recorded: the EEPROM, the
// comparison with the host simulation, the loop timing, the ISR timing,
// torn reads (scenario_expect.hpp).
#include "scenario/scenario_expect.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <tuple>
#include <type_traits>

#include "common/csv_table.hpp"
#include "comparison.hpp"
#include "hostsim/host_sim.hpp"
#include "race_report.hpp"
#include "scenario/step_failed.hpp"

namespace ddmr::tools::scenario {

std::string printable(const std::string& s) {
    std::string out;
    for (const char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '\n') out += "\\n";
        else if (c == '\r') out += "\\r";
        else if (u < 0x20 || u >= 0x7F) out += fmt::format("\\x{:02x}", u);
        else out.push_back(c);
    }
    return out;
}

std::string expect_eeprom(const hil::EepromImage& image, const std::vector<hil::EepromLogSample>& log,
                          const ExpectEeprom& e) {
    std::string note;
    if (e.bin) {
        std::ifstream in(*e.bin, std::ios::binary);
        const std::string want((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (want.size() != image.size()) {
            throw StepFailed{Verdict::kFail, fmt::format("{} has {} bytes, the EEPROM {}", e.bin->string(), want.size(), image.size())};
        }
        for (std::size_t a = 0; a < image.size(); ++a) {
            if (static_cast<uint8_t>(want[a]) != image[a]) {
                throw StepFailed{Verdict::kFail, fmt::format("EEPROM byte 0x{:03x}: expected 0x{:02x}, got 0x{:02x}", a,
                                                             static_cast<uint8_t>(want[a]), image[a])};
            }
        }
        note = fmt::format("{} bytes equal", image.size());
    }
    if (e.log) {
        Table want;
        try {
            want = read_table(*e.log);
        } catch (const std::exception& ex) {
            throw StepFailed{Verdict::kFail, ex.what()};
        }
        const auto& wx = want.col("x_m", *e.log);
        const auto& wy = want.col("y_m", *e.log);
        const std::size_t k = want.rows();
        if (k != log.size()) {
            throw StepFailed{Verdict::kFail, fmt::format("the EEPROM log has {} samples, {} has {}", log.size(),
                                                         e.log->filename().string(), k)};
        }
        double worst = 0.0;
        for (std::size_t i = 0; i < k; ++i) {
            const double d = std::hypot(log[i].x_m - wx[i], log[i].y_m - wy[i]);
            worst = std::max(worst, d);
            if (d > e.tol_m) {
                throw StepFailed{Verdict::kFail, fmt::format("EEPROM log sample {}: ({:.3f}, {:.3f}) is {:.4f} m from "
                                                             "({:.3f}, {:.3f}) in {}, tolerance {} m",
                                                             i + 1, log[i].x_m, log[i].y_m, d, wx[i], wy[i],
                                                             e.log->filename().string(), e.tol_m)};
            }
        }
        note += fmt::format("{}{} samples within {:.4f} m", note.empty() ? "" : "; ", k, worst);
    }
    return note;
}

std::string expect_compare(const Scenario& s_, const std::vector<hil::EepromLogSample>& log, const ExpectCompare& e) {
    if (log.empty()) throw StepFailed{Verdict::kFail, "the EEPROM log is empty: nothing to compare"};
    namespace hs = ddmr::hostsim;
    hs::SimConfig c = hs::config_for_case(e.test_case, hs::Model::firmware);
    c.plant = s_.plant;
    c.pwm = s_.pwm == plant::DriveMode::switched ? hs::PwmModel::switched : hs::PwmModel::averaged;
    c.fidelity = hs::Fidelity::all();
    c.duration_s = std::max(c.duration_s, static_cast<double>(kIterationsPerLogSample * log.size()) * c.period_s + 0.05);
    hs::validate(c);
    const hs::SimResult sim = hs::simulate(c);
    std::vector<Point2> logged;
    logged.reserve(log.size());
    for (const auto& p : log) logged.push_back({p.x_m, p.y_m});
    const PairMetrics m = compare_tracks(logged, sim_track(sim, c, logged.size()));
    if (m.rms_m > e.max_rms_m || (e.max_endpoint_m && m.endpoint_m > *e.max_endpoint_m)) {
        throw StepFailed{Verdict::kFail,
                         fmt::format("EEPROM log vs host simulation (case {}): rms {:.4f} m (max {}), endpoint {:.4f} m{}",
                                     e.test_case, m.rms_m, e.max_rms_m, m.endpoint_m,
                                     e.max_endpoint_m ? fmt::format(" (max {})", *e.max_endpoint_m) : "")};
    }
    return fmt::format("rms {:.4f} m, endpoint {:.4f} m over {} samples", m.rms_m, m.endpoint_m, m.samples);
}

std::string expect_loop(hil::Session& session, hil::LoopProfiler& profiler, const ExpectLoop& e) {
    hil::RobotRig* rig_ = &session.rig();
    const uint32_t clock_hz = session.core().clock_hz();
    const auto us = [clock_hz](auto cycles) {
        if constexpr (std::is_floating_point_v<decltype(cycles)>) {
            return cycles * 1e6 / clock_hz;
        } else {
            return hil::cycles_to_s(cycles, clock_hz) * 1e6;
        }
    };
    if (!e.include_eeprom_writes && !rig_->eeprom_timing().all_writes_recorded()) {
        throw StepFailed{Verdict::kFail,
                         fmt::format("include_eeprom_writes: false needs every EEPROM write, but only the first {} "
                                     "of {} are recorded",
                                     rig_->eeprom_timing().writes().size(), rig_->eeprom_timing().write_count())};
    }
    std::vector<Cycles> write_cycles;
    for (const auto& w : rig_->eeprom_timing().writes()) write_cycles.push_back(w.cycle);
    profiler.tag_eeprom_writes(write_cycles);
    std::vector<Cycles> compute, period;
    for (const auto& it : profiler.iterations()) {
        if (!e.include_eeprom_writes && it.eeprom_write) continue;
        compute.push_back(it.compute());
        period.push_back(it.period());
    }
    if (compute.empty()) throw StepFailed{Verdict::kFail, "no complete control-loop iteration was seen"};
    const auto c = hil::cycle_distribution(compute);
    const auto p = hil::cycle_distribution(period);
    const std::vector<std::tuple<const char*, const Range*, double>> checks = {
        {"max_us", &e.max_us, us(c.max)},          {"p99_us", &e.p99_us, us(c.p99)},
        {"mean_us", &e.mean_us, us(c.mean)},
        {"period_max_us", &e.period_max_us, us(p.max)}, {"period_p99_us", &e.period_p99_us, us(p.p99)},
        {"period_mean_us", &e.period_mean_us, us(p.mean)},
    };
    for (const auto& [name, range, value] : checks) {
        if (range->set() && !range->contains(value)) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} in [{}, {}], got {:.1f} ({} iterations)", name,
                                                         range->min ? fmt::format("{}", *range->min) : "-",
                                                         range->max ? fmt::format("{}", *range->max) : "-", value,
                                                         c.count)};
        }
    }
    return fmt::format("{} iterations: compute max {:.1f} p99 {:.1f} mean {:.1f} us; period max {:.1f} p99 {:.1f} mean {:.1f} us",
                       c.count, us(c.max), us(c.p99), us(c.mean), us(p.max),
                       us(p.p99), us(p.mean));
}

std::string expect_isr(hil::IsrMonitor& monitor, const ExpectIsr& e) {
    const hil::IsrSummary s = monitor.summary();
    for (const auto& v : s.vectors) {
        if (v.name != e.vector) continue;
        if (e.min_count && v.count < *e.min_count) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} to run at least {} times, it ran {}", e.vector, *e.min_count, v.count)};
        }
        if (e.max_latency_cycles && v.latency.max > *e.max_latency_cycles) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} entry latency <= {} cycles, worst {} cycles",
                                                         e.vector, *e.max_latency_cycles, v.latency.max)};
        }
        if (e.max_duration_cycles && v.duration.max > *e.max_duration_cycles) {
            throw StepFailed{Verdict::kFail, fmt::format("expected {} duration <= {} cycles, longest {} cycles",
                                                         e.vector, *e.max_duration_cycles, v.duration.max)};
        }
        return fmt::format("{}: {} entries, latency max {} cycles, duration max {} cycles", v.name, v.count,
                           v.latency.max, v.duration.max);
    }
    if (e.min_count && *e.min_count == 0) return fmt::format("{} never ran", e.vector);
    throw StepFailed{Verdict::kFail, fmt::format("interrupt {} never ran", e.vector)};
}

std::string expect_no_torn_reads(const hil::RaceDetector& races, const ExpectNoTornReads& e) {
    std::string note;
    uint64_t observed = 0;
    for (const hil::SplitAccess& a : races.splits()) {
        if (!races.is_race(a)) continue;
        const std::string& name = races.objects()[a.object].name;
        if (!e.variables.empty() && std::find(e.variables.begin(), e.variables.end(), name) == e.variables.end()) {
            continue;
        }
        if (a.observed == 0) continue;
        observed += a.observed;
        note += fmt::format("{}{} {} of {} at 0x{:04x} ({}x)", note.empty() ? "" : "; ",
                            a.kind == hil::AccessKind::kRead ? "read" : "write", "torn", name, a.pc, a.observed);
    }
    if (observed > 0) throw StepFailed{Verdict::kFail, "torn values observed: " + note + " (isr.md lists them)"};
    const nlohmann::json counts = torn_reads_summary(races);
    std::string seen;
    for (const auto& [name, c] : counts.items()) {
        if (!e.variables.empty() && std::find(e.variables.begin(), e.variables.end(), name) == e.variables.end()) {
            continue;
        }
        seen += fmt::format("{}{}: {} reads split by a writing ISR, {} changed mid-read", seen.empty() ? "" : "; ",
                            name, c["split_reads"].get<uint64_t>(), c["torn"].get<uint64_t>());
    }
    return fmt::format("no torn value observed ({} interrupt entries checked){}{}",
                       races.stats().entries_checked, seen.empty() ? "" : ": ", seen);
}

void check_firmware_names(const Scenario& s) {
    const auto elf = hil::ElfImage::read(s.firmware);
    const hil::DataObjects objects(elf, *hil::board_description(s.board.model).mcu);
    const hil::McuDescription& mcu = *hil::board_description(s.board.model).mcu;
    // expect-var: a variable in SRAM whose size the type (given, or by size) matches.
    for (const Step& step : s.steps) {
        const auto* e = std::get_if<ExpectVar>(&step.action);
        if (e == nullptr) continue;
        const std::string where = fmt::format("{}:{}: expect-var: ", s.file.string(), step.line);
        const auto sym = elf.find(e->name);
        if (!sym) {
            throw std::invalid_argument(where + fmt::format("the firmware has no symbol '{}' (not a global, or folded "
                                                            "away by LTO)",
                                                            e->name));
        }
        if (!sym->is_object || sym->address < mcu.sram_start || sym->address + sym->size - 1 > mcu.ram_end) {
            throw std::invalid_argument(where + fmt::format("'{}' is not a variable in SRAM", e->name));
        }
        if (!e->type) {
            if (!hil::default_var_type(sym->size, hil::FourByteDefault::kNone)) {
                throw std::invalid_argument(where + fmt::format("'{}' has {} bytes: give its type (type: int32, uint32 or "
                                                                "float)",
                                                                e->name, sym->size));
            }
        } else if (hil::var_type_size(*e->type) != sym->size) {
            throw std::invalid_argument(where + fmt::format("'{}' is {} bytes; {} is {}", e->name, sym->size,
                                                            hil::to_string(*e->type), hil::var_type_size(*e->type)));
        }
    }
    // Variables named by expect-no-torn-reads must be multi-byte variables in SRAM.
    for (const Step& step : s.steps) {
        const auto* e = std::get_if<ExpectNoTornReads>(&step.action);
        if (e == nullptr) continue;
        for (const std::string& name : e->variables) {
            const auto o = objects.find(name);
            if (!o) {
                throw std::invalid_argument(fmt::format("{}:{}: expect-no-torn-reads: the firmware has no variable '{}' in SRAM",
                                                        s.file.string(), step.line, name));
            }
            const uint16_t size = objects[*o].size;
            if (size < 2 || size > hil::RaceDetector::kMaxVariableBytes) {
                throw std::invalid_argument(fmt::format("{}:{}: expect-no-torn-reads: '{}' has {} byte(s); a torn access needs 2..{}",
                                                        s.file.string(), step.line, name, size,
                                                        hil::RaceDetector::kMaxVariableBytes));
            }
        }
    }
}

}  // namespace ddmr::tools::scenario
