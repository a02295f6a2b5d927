#include "session_outputs.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <iterator>

namespace ddmr::tools {

LoopTraceOutput::LoopTraceOutput(hil::LoopTracer& tracer, const RunPlan& plan, const std::filesystem::path& file,
                                 uint32_t clock_hz, hil::VcdRecorder* vcd)
    : tracer_(tracer), csv_(file), clock_hz_(clock_hz), vcd_(vcd) {
    std::string header = "iteration,cycle,t_avr_s";
    for (const auto& v : plan.traced) header += "," + v.name;
    csv_.write(header + "\n");
    t_index_ = static_cast<std::size_t>(
        std::find_if(plan.traced.begin(), plan.traced.end(),
                     [&](const auto& v) { return v.name == plan.loop_marker->name; }) -
        plan.traced.begin());
    tracer_.set_sink([this](Cycles cycle, const std::vector<double>& values) { on_sample(cycle, values); });
}

void LoopTraceOutput::on_sample(Cycles cycle, const std::vector<double>& values) {
    const double t = values[t_index_];
    if (t > last_t_) {
        ++iterations_;
        row_.clear();
        fmt::format_to(std::back_inserter(row_), "{},{},{:.7f}", iterations_, cycle,
                       hil::cycles_to_s(cycle, clock_hz_));
        for (double v : values) fmt::format_to(std::back_inserter(row_), ",{:.9g}", v);
        row_.push_back('\n');
        csv_.write(row_);
        if (vcd_ != nullptr) vcd_->mark_loop_iteration(cycle);
        if (have_last_) {
            sum_ += cycle - last_cycle_;
            ++count_;
        }
        have_last_ = true;
        last_cycle_ = cycle;
    } else {
        have_last_ = false;
    }
    last_t_ = t;
}

TraceOutput::TraceOutput(hil::Session& session, const RunPlan& plan, const FirmwareRunOptions& options)
    : session_(session),
      tracer_(session.rig().variables(), plan.loop_marker.value_or(plan.trace_vars.front()), plan.trace_vars),
      csv_(options.out_dir / "trace.csv"),
      per_iteration_(options.trace_every_cycles == 0) {
    for (const auto& v : plan.trace_vars) handles_.push_back(session.rig().variables().lookup(v.name, v.type));
    std::string header = per_iteration_ ? "iteration,cycle,t_avr_s" : "row,cycle,t_avr_s";
    for (const auto& v : plan.trace_vars) header += "," + v.name;
    csv_.write(header + "\n");
    if (per_iteration_) {
        tracer_.set_sink([this](Cycles cycle, const std::vector<double>& values) { write_row(cycle, values); });
    } else {
        session.every(options.trace_every_cycles, [this](Cycles cycle) {
            values_.clear();
            for (const auto& h : handles_) values_.push_back(session_.rig().variables().read(h));
            write_row(cycle, values_);
        });
    }
}

void TraceOutput::write_row(Cycles cycle, const std::vector<double>& values) {
    std::string r = fmt::format("{},{},{:.7f}", ++rows_, cycle, session_.seconds(cycle));
    for (double v : values) fmt::format_to(std::back_inserter(r), ",{:.9g}", v);
    r.push_back('\n');
    csv_.write(r);
}

}  // namespace ddmr::tools
