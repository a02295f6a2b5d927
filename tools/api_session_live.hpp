#pragma once
// ApiSession's insides, shared by its two source files (api_session.cpp:
// set-up, runs and reads; api_session_acts.cpp: acts on the robot, the log
// and snapshots). Not part of the interface.

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "api_session.hpp"
#include "common/truth_csv.hpp"
#include "hil/pin_driver.hpp"
#include "hil/pin_waveforms.hpp"
#include "scenario/fault_steps.hpp"

namespace ddmr::tools {

/// What the host receives and the plant's truth, kept for the caller; it
/// stops the running chunk when the awaited text arrives.
class ApiSession::Observer final : public hil::SessionObserver {
public:
    Observer(hil::Session& session, std::vector<double>& truth_rows) : session_(session), truth_rows_(truth_rows) {}
    void on_host_byte(char c, hil::Cycles /*cycle*/) override {
        text_.push_back(c);
        if (!awaited_.empty() && !seen_ && text_.size() >= from_ + awaited_.size() &&
            text_.compare(text_.size() - awaited_.size(), awaited_.size(), awaited_) == 0) {
            seen_ = true;
            session_.interrupt();
        }
    }
    void on_truth(const hil::TruthSample& s) override {
        append_truth_values(truth_rows_, s, /*with_drive=*/true);
        values_.clear();
        session_.rig().extra_truth_values(values_);
        truth_rows_.insert(truth_rows_.end(), values_.begin(), values_.end());
    }
    void await(const std::string& text) {
        awaited_ = text;
        from_ = text_.size();
        seen_ = false;
    }
    bool seen() const { return seen_; }
    const std::string& text() const { return text_; }

private:
    hil::Session& session_;
    std::vector<double>& truth_rows_;
    std::string text_;
    std::string awaited_;
    std::size_t from_ = 0;
    bool seen_ = false;
    std::vector<double> values_;
};

/// One run of the session, from reset: what restore() builds again.
struct ApiSession::Live {
    std::filesystem::path staging;
    std::unique_ptr<FirmwareRun> run;
    std::vector<double> truth_rows;
    std::unique_ptr<Observer> observer;
    std::unique_ptr<scenario::FaultSteps> faults;
    std::unique_ptr<hil::PinDriver> driver;  ///< pin_drive's, built at its first use
    std::map<int, std::unique_ptr<hil::PinWaveforms>> waveforms;
    std::vector<std::string> truth_columns;
    std::vector<ApiAction> log;
    std::size_t read_mark = 0;
    hil::SessionStop last_stop = hil::SessionStop::kReachedCycle;
    std::string ended;  ///< why the run cannot go on ("" while it can)
    std::string exit_reason;

    Live(const ApiOptions& options, const nlohmann::json& firmware_source);
    ~Live();
    Live(const Live&) = delete;
    Live& operator=(const Live&) = delete;
};

}  // namespace ddmr::tools
