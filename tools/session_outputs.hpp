#pragma once
// The streamed outputs of a session, as observers: truth.csv (the plant's
// ground truth), firmware.csv (the contract's globals per control-loop
// iteration), trace.csv (--trace) and the VCD (--vcd). Each writes through
// an AtomicFileWriter: renamed into place by commit() at the end.

#include <fmt/format.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/truth_csv.hpp"
#include "firmware_run.hpp"
#include "firmware_run_plan.hpp"
#include "hil/loop_tracer.hpp"
#include "hil/parts/part_set.hpp"
#include "hil/session.hpp"
#include "hil/vcd_recorder.hpp"
#include "hil/vcd_writer.hpp"

namespace ddmr::tools {

using hil::Cycles;

/// truth.csv: the plant's ground truth, streamed; then the world's columns
/// (line_offset_m, wall_distance_m) and one column per part's truth value
/// ("shield.Q": the 74HC595's output byte), when there are any
/// (RobotRig::extra_truth_columns).
class TruthOutput final : public hil::SessionObserver {
public:
    TruthOutput(const std::filesystem::path& file, const hil::RobotRig& rig) : csv_(file), rig_(rig) {
        std::string header = truth_csv_header(/*with_drive=*/true);
        header.pop_back();  // its newline
        const std::vector<std::string> extra = rig_.extra_truth_columns();
        for (const std::string& c : extra) header += "," + c;
        extra_ = !extra.empty();
        csv_.write(header + "\n");
    }
    void on_truth(const hil::TruthSample& s) override {
        row_.clear();
        append_truth_row(row_, s, /*with_drive=*/true);
        if (extra_) {
            row_.pop_back();
            values_.clear();
            rig_.extra_truth_values(values_);
            for (const double v : values_) row_ += fmt::format(",{}", v);
            row_ += '\n';
        }
        csv_.write(row_);
    }
    void commit() { csv_.commit(); }

private:
    AtomicFileWriter csv_;
    const hil::RobotRig& rig_;
    bool extra_ = false;
    std::string row_;
    std::vector<double> values_;
};

/// firmware.csv: the contract's globals once per control-loop iteration, and
/// the loop period. A control-loop iteration is an increase of the marker:
/// one definition for loop_iterations, firmware.csv's rows (its `iteration`
/// column counts them from 1) and the loop period. A change that is not an
/// increase (the reference sketch zeroes t after its report) is no
/// iteration and has no row.
class LoopTraceOutput final : public hil::SessionObserver {
public:
    LoopTraceOutput(hil::LoopTracer& tracer, const RunPlan& plan, const std::filesystem::path& file,
                    uint32_t clock_hz, hil::VcdRecorder* vcd);
    void on_boundary(Cycles cycle) override { tracer_.poll(cycle); }
    void commit() { csv_.commit(); }
    uint64_t iterations() const { return iterations_; }
    double mean_period_s() const {
        return count_ > 0 ? hil::cycles_to_s(sum_, clock_hz_) / static_cast<double>(count_) : 0.0;
    }

private:
    void on_sample(Cycles cycle, const std::vector<double>& values);

    hil::LoopTracer& tracer_;
    AtomicFileWriter csv_;
    uint32_t clock_hz_;
    hil::VcdRecorder* vcd_;
    std::size_t t_index_ = 0;
    std::string row_;
    double last_t_ = 0.0;
    Cycles last_cycle_ = 0;
    bool have_last_ = false;
    Cycles sum_ = 0;
    uint64_t count_ = 0;
    uint64_t iterations_ = 0;
};

/// trace.csv: the --trace globals per loop iteration or every N cycles.
class TraceOutput final : public hil::SessionObserver {
public:
    TraceOutput(hil::Session& session, const RunPlan& plan, const FirmwareRunOptions& options);
    void on_boundary(Cycles cycle) override {
        if (per_iteration_) tracer_.poll(cycle);
    }
    void commit() { csv_.commit(); }

private:
    void write_row(Cycles cycle, const std::vector<double>& values);

    hil::Session& session_;
    hil::LoopTracer tracer_;  ///< validates every name and size (the marker only matters per iteration)
    std::vector<hil::Variable> handles_;
    AtomicFileWriter csv_;
    bool per_iteration_;
    uint64_t rows_ = 0;
    std::vector<double> values_;
};

/// --vcd: a recorder on the rig, streaming to the atomic file.
class VcdOutput final : public hil::SessionObserver {
public:
    VcdOutput(hil::Session& session, const std::filesystem::path& file, const hil::LoopProfiler* profiler)
        : file_(file), writer_([this](std::string_view text) { file_.write(text); }, config(session)),
          recorder_(session.rig(), session.elf(), writer_, profiler) {}
    void on_boundary(Cycles cycle) override { recorder_.on_boundary(cycle); }
    hil::VcdRecorder& recorder() { return recorder_; }
    void finish() { recorder_.finish(); }
    void commit() { file_.commit(); }

private:
    static hil::VcdConfig config(hil::Session& session) {
        hil::VcdConfig c;
        c.clock_hz = session.core().clock_hz();
        return c;
    }
    AtomicFileWriter file_;
    hil::VcdWriter writer_;
    hil::VcdRecorder recorder_;
};

}  // namespace ddmr::tools
