#pragma once
// SketchContract: what the HIL needs to know about one firmware, as data: a
// small YAML file beside the sketch (docs/contracts.md; the reference
// sketch's is firmware/ddmr_tracking/hil.yaml). Every section is optional;
// without a contract `run` runs --seconds of simulated time.
//
//   start:     what to send the firmware, and when: after it first returns
//              from a function, at an AVR time, or once a text has arrived
//   complete:  when the run is complete: a text (and N more lines), or the
//              end of a report in a known format
//   report:    the report's format (ddmr-tracking: the thesis sketch's,
//              hil/firmware_report.hpp), or named fields, each a regular
//              expression whose first group is a number, parsed into
//              summary.json
//   pose:      the float globals of the firmware's pose estimate, read when
//              a text arrives (or at the end of the run)
//   loop:      a global that changes once per control-loop iteration
//              (firmware.csv rows) and the function the profile marks
//              iterations with
//   trace:     the globals firmware.csv holds, "name" or "name:type"
//   eeprom-log: where the sketch logs (x, y) samples in the EEPROM
//              (hil/eeprom_log.hpp's EepromLogLayout)

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "hil/eeprom_log.hpp"

namespace ddmr::hil {

struct ContractStart {
    std::string send;           ///< bytes to send; "{case}" becomes run --case N
    std::vector<int> cases;     ///< the values --case takes (empty: the text has no {case})
    int default_case = 0;       ///< the first of `cases`
    /// When to send (exactly one): the firmware's first return from this
    /// function, this AVR time [s], or once this text has been received.
    std::optional<std::string> after_return;
    std::optional<double> at_s;
    std::optional<std::string> after_text;
};

enum class ReportFormat { kNone, kDdmrTracking, kFields };

/// A report field: the last line the pattern (ECMAScript regex) matches
/// gives the value, its first capture group read as a number.
struct ReportField {
    std::string name;
    std::string pattern;
};

struct ContractComplete {
    std::optional<std::string> text;  ///< complete when this text has been received ...
    int lines_after = 0;              ///< ... the rest of its line, and this many more lines (ended by '\n')
    bool report = false;              ///< complete when the report (format below) has ended
};

struct ContractPose {
    std::string x, y, theta;           ///< float globals [m], [m], [rad]
    std::optional<std::string> at_text;  ///< read when this text arrives (else at the end of the run)
};

struct ContractLoop {
    std::optional<std::string> marker;    ///< a global ("name" or "name:type") that changes once per iteration
    std::optional<std::string> function;  ///< the profile's loop mark (one call per iteration)
};

struct SketchContract {
    std::string source;  ///< the file it came from
    std::optional<ContractStart> start;
    std::optional<ContractComplete> complete;
    ReportFormat report = ReportFormat::kNone;
    std::vector<ReportField> report_fields;  ///< with ReportFormat::kFields
    std::optional<ContractPose> pose;
    ContractLoop loop;
    std::vector<std::string> trace;  ///< firmware.csv's columns
    std::optional<EepromLogLayout> eeprom_log;

    /// The start text for `test_case` ("{case}" replaced); throws
    /// std::invalid_argument if the contract does not take that case.
    std::string start_text(int test_case) const;
};

/// Reads and checks a contract file; throws std::runtime_error
/// "FILE:LINE: key 'K': ..." naming the first problem.
SketchContract load_sketch_contract(const std::filesystem::path& path);

/// The ReportFormat's name in the file ("none", "ddmr-tracking", "fields").
const char* to_string(ReportFormat f);

}  // namespace ddmr::hil
