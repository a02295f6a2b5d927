#pragma once
// ContractWatch: what `ddmr-hil run` reads in the bytes the host receives,
// as a Session observer. Every byte goes to uart.txt; the sketch contract's
// texts are watched for (its start text's cue, the pose text, the
// completion text and its lines after), its report is parsed and its report
// fields matched line by line; with --unity, Unity's summary ends the run.
// It acts on the session only through post(), end_run() and end_after().

#include <functional>
#include <optional>
#include <regex>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/unity_summary.hpp"
#include "firmware_run_plan.hpp"
#include "hil/firmware_report.hpp"
#include "hil/session.hpp"
#include "plant/diff_drive_kinematics.hpp"

namespace ddmr::tools {

/// Sees a text go by in a byte stream (a contract's start, pose and
/// completion texts); an empty text is never seen.
class TextWatch {
public:
    explicit TextWatch(std::string text) : text_(std::move(text)) {}
    /// Feeds one byte; true the first time the text is complete.
    bool feed(char c);
    bool seen() const { return seen_; }

private:
    std::string text_;
    std::string window_;
    bool seen_ = false;
};

class ContractWatch final : public hil::SessionObserver {
public:
    /// `uart_txt` receives every byte; `on_start_cue` is posted to the
    /// session when the contract's start.after-text arrives.
    ContractWatch(hil::Session& session, const RunPlan& plan, bool unity, AtomicFileWriter& uart_txt,
                  std::function<void()> on_start_cue);

    void on_host_byte(char c, hil::Cycles cycle) override;
    /// Whether the start cue and the completion act on the session (default
    /// on); off, they are only noted (a front end drives the run itself).
    void set_driving(bool driving) { driving_ = driving; }
    /// The plan's case changed before the run (FirmwareRun::set_case): the
    /// report's shape follows the case.
    void case_changed();
    /// A last line without '\n' is matched against the report fields.
    void finish();

    bool done() const { return done_; }  ///< the contract's completion (or Unity's summary) came
    bool start_seen() const { return start_watch_.seen(); }
    const hil::FirmwareReportParser& parser() const { return parser_; }
    const std::optional<UnitySummary>& unity() const { return unity_summary_; }
    bool unity_counts_seen() const { return unity_watch_.counts_seen(); }
    /// The firmware's pose globals, read as the pose text arrived (or by read_pose()).
    const std::optional<plant::Pose>& firmware_pose() const { return pose_; }
    void read_pose();
    bool has_pose() const { return pose_x_.has_value(); }
    /// The report fields' last values, by the contract's names (null: never matched).
    nlohmann::json fields_json() const;

private:
    void match_fields();
    void watch_completion(char c);
    void feed_report(char c);

    hil::Session& session_;
    const RunPlan& plan_;
    bool unity_ = false;
    AtomicFileWriter& uart_txt_;
    std::function<void()> on_start_cue_;
    hil::FirmwareReportParser parser_;
    TextWatch start_watch_;
    TextWatch pose_watch_;
    TextWatch done_watch_;
    UnitySummaryWatch unity_watch_;
    std::optional<UnitySummary> unity_summary_;
    int lines_to_go_ = 0;  ///< lines-after: the end of the text's own line, then that many more
    bool done_ = false;
    bool driving_ = true;
    std::optional<hil::Variable> pose_x_, pose_y_, pose_theta_;
    std::optional<plant::Pose> pose_;
    std::vector<std::regex> field_patterns_;
    std::vector<std::optional<double>> field_values_;
    std::string field_line_;
};

}  // namespace ddmr::tools
