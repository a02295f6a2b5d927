#pragma once
// The scenario steps that check what a whole run recorded, as functions of
// the session's parts: each returns its note, or throws StepFailed with
// what was expected and what happened.

#include <string>
#include <vector>

#include "hil/eeprom_log.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/isr_monitor.hpp"
#include "hil/loop_profiler.hpp"
#include "hil/race_detector.hpp"
#include "hil/session.hpp"
#include "scenario/scenario.hpp"

namespace ddmr::tools::scenario {

/// expect-eeprom: the image against its .bin, the decoded log against its CSV.
std::string expect_eeprom(const hil::EepromImage& image, const std::vector<hil::EepromLogSample>& log,
                          const ExpectEeprom& e);
/// expect-compare: the EEPROM log against the host simulation of the case.
std::string expect_compare(const Scenario& s, const std::vector<hil::EepromLogSample>& log, const ExpectCompare& e);
/// expect-loop: the control loop's compute and period times.
std::string expect_loop(hil::Session& session, hil::LoopProfiler& profiler, const ExpectLoop& e);
/// expect-isr: a vector's entry count, latency and duration.
std::string expect_isr(hil::IsrMonitor& monitor, const ExpectIsr& e);
/// expect-no-torn-reads: no torn value observed on the named variables.
std::string expect_no_torn_reads(const hil::RaceDetector& races, const ExpectNoTornReads& e);

}  // namespace ddmr::tools::scenario
