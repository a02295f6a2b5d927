#include "contract_watch.hpp"

#include <cstdio>
#include <cstdlib>

namespace ddmr::tools {

namespace {
/// A report-field line longer than this is cut (bounded memory on a flood).
constexpr std::size_t kMaxFieldLine = 4096;
}  // namespace

bool TextWatch::feed(char c) {
    if (text_.empty() || seen_) return false;
    window_.push_back(c);
    if (window_.size() > text_.size()) window_.erase(window_.begin());
    seen_ = window_ == text_;
    return seen_;
}

ContractWatch::ContractWatch(hil::Session& session, const RunPlan& plan, bool unity, AtomicFileWriter& uart_txt,
                             std::function<void()> on_start_cue)
    : session_(session),
      plan_(plan),
      unity_(unity),
      uart_txt_(uart_txt),
      on_start_cue_(std::move(on_start_cue)),
      // The ddmr-tracking report's EEPROM dump follows only case 1's report.
      parser_(/*expects_eeprom_dump=*/plan.test_case == 1),
      start_watch_(plan.has_start && plan.contract->start->after_text ? *plan.contract->start->after_text : ""),
      pose_watch_(plan.contract && plan.contract->pose && plan.contract->pose->at_text ? *plan.contract->pose->at_text
                                                                                     : ""),
      done_watch_(plan.contract_completes && plan.contract->complete->text ? *plan.contract->complete->text : "") {
    const auto& contract = plan.contract;
    if (plan.contract_completes && contract->complete->text) {
        lines_to_go_ = contract->complete->lines_after + (contract->complete->text->back() == '\n' ? 0 : 1);
    }
    // The firmware's pose estimate, read as the contract's text arrives (the
    // reference sketch reuses Ex/Ey right after "END") or at the end.
    if (contract && contract->pose) {
        hil::FirmwareVariables& vars = session.rig().variables();
        pose_x_ = vars.lookup(contract->pose->x, hil::VarType::kFloat);
        pose_y_ = vars.lookup(contract->pose->y, hil::VarType::kFloat);
        pose_theta_ = vars.lookup(contract->pose->theta, hil::VarType::kFloat);
    }
    // Report fields (the contract's report: {fields}): each line is matched
    // against every pattern; the last match of each gives its value.
    if (contract) {
        for (const auto& f : contract->report_fields) field_patterns_.emplace_back(f.pattern);
    }
    field_values_.resize(field_patterns_.size());
}

void ContractWatch::read_pose() {
    const auto& vars = session_.rig().variables();
    pose_ = plant::Pose{vars.read(*pose_x_), vars.read(*pose_y_), vars.read(*pose_theta_)};
}

void ContractWatch::match_fields() {
    for (std::size_t i = 0; i < field_patterns_.size(); ++i) {
        std::smatch m;
        if (!std::regex_search(field_line_, m, field_patterns_[i]) || m.size() < 2) continue;
        const std::string text = m[1].str();
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        field_values_[i] = (end != text.c_str()) ? std::optional<double>(v) : std::nullopt;
    }
    field_line_.clear();
}

void ContractWatch::finish() {
    if (!field_line_.empty()) match_fields();
}

nlohmann::json ContractWatch::fields_json() const {
    if (field_patterns_.empty()) return nullptr;
    nlohmann::json f = nlohmann::json::object();
    for (std::size_t i = 0; i < field_patterns_.size(); ++i) {
        f[plan_.contract->report_fields[i].name] = field_values_[i] ? nlohmann::json(*field_values_[i]) : nullptr;
    }
    return f;
}

void ContractWatch::on_host_byte(char c, hil::Cycles /*cycle*/) {
    uart_txt_.write(std::string_view(&c, 1));
    if (!field_patterns_.empty()) {
        if (c == '\n') {
            match_fields();
        } else if (c != '\r' && field_line_.size() < kMaxFieldLine) {
            field_line_.push_back(c);
        }
    }
    if (start_watch_.feed(c) && driving_) session_.post(on_start_cue_);  // the start text goes out now
    if (pose_watch_.feed(c) && !pose_) read_pose();
    if (unity_) {
        std::fputc(c, stdout);  // pio test reads Unity's lines from stdout as they come
        if (c == '\n') std::fflush(stdout);
        if (!done_ && unity_watch_.feed(c)) {
            done_ = true;
            unity_summary_ = unity_watch_.summary();
            if (driving_) session_.end_after(session_.rig().uart().cycles_per_byte());  // the last byte has left the wire
        }
    }
    watch_completion(c);
    if (plan_.reports) feed_report(c);
}

void ContractWatch::case_changed() { parser_ = hil::FirmwareReportParser(/*expects_eeprom_dump=*/plan_.test_case == 1); }

void ContractWatch::watch_completion(char c) {
    if (!plan_.contract_completes || !plan_.contract->complete->text || done_) return;
    if (done_watch_.seen()) {
        if (c == '\n') --lines_to_go_;
    } else {
        done_watch_.feed(c);
    }
    if (done_watch_.seen() && lines_to_go_ <= 0) {
        done_ = true;
        if (driving_) session_.end_after(session_.rig().uart().cycles_per_byte());  // the last byte has left the wire
    }
}

void ContractWatch::feed_report(char c) {
    const bool was_done = parser_.complete() || parser_.error().has_value();
    parser_.feed(std::string_view(&c, 1));
    if (was_done) return;
    if (parser_.error()) {
        if (driving_) session_.end_run();
    } else if (parser_.complete() && plan_.contract_completes && plan_.contract->complete->report) {
        done_ = true;
        if (driving_) session_.end_after(session_.rig().uart().cycles_per_byte());  // the last byte has left the wire
    }
}

}  // namespace ddmr::tools
