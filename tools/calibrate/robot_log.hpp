#pragma once
// A real robot's run as its serial dump records it (issue 18's LOG): what
// the reference sketch prints at the end of a case (firmware/ddmr_tracking,
// ../shared/reference/ddmr_tracking.ino lines 243-282):
//
//   0.6m                        case banner (optional: "0.6m" case 1, "0.4m" case 2)
//   END
//   7548                        Count1: right encoder edges  (required)
//   5659                        Count2: left encoder edges   (required)
//   Gx,0.585,Gy,-0.112,t,12.000 report lines "Key,value,Key,value..." (optional:
//   ...                         an older build printed fewer)
//   240                         addr: EEPROM bytes used per axis (optional)
//   0.000 , 0.000               the EEPROM dump: EEPROM.read(j) / 250.0 and
//   0.024 , 0.000               EEPROM.read(j + 500) / 250.0, 3 decimals, for
//   ...                         j = 0, 2, ..., addr             (required, >= 3 lines)
//   1.020 , 1.020               j = addr: a byte this run never wrote (erased,
//                               or an earlier run's): not a sample. With addr
//                               printed this line may be missing (a copy from
//                               a serial monitor often lacks it): read with a
//                               warning
//
// Each dump value is an EEPROM byte b over 250 (0, 0.004, ..., 1.020): the
// low 8 bits of int(E x 250), E the firmware's pose estimate [m]. The reader
// recovers the bytes exactly and leaves their interpretation (truncation
// cells, wrap-around) to the objective (log_residual.hpp).
//
// Lines before END that are not the banner are ignored (a robot may print
// anything while it drives); a file with more than one END holds more than
// one run and is refused. Errors are one line "FILE:LINE: what is wrong".

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ddmr::calibrate {

/// One line of the EEPROM dump: the bytes at 2k and 2k + 500.
struct LoggedSample {
    uint8_t x_byte = 0;
    uint8_t y_byte = 0;
    int line = 0;  ///< line in the file
};

struct RobotLog {
    std::string source;                  ///< file name, for messages
    std::optional<int> case_number;      ///< from the banner
    uint64_t count1 = 0;                 ///< right encoder edges (Count1)
    uint64_t count2 = 0;                 ///< left encoder edges (Count2)
    /// Report values by key ("Gx", "Ex", "Thta", ...), when printed.
    std::map<std::string, double> fields;
    std::optional<uint64_t> addr;        ///< EEPROM bytes used per axis, when printed
    std::vector<LoggedSample> samples;   ///< the dump's logged samples, in order (not its last line)
    /// The dump's last line (j = addr), kept for messages; none when the
    /// file lacks it (addr printed, one line fewer than it promises).
    std::optional<LoggedSample> unwritten;
    /// What was read but should be said, one line each ("SOURCE: ..."): a
    /// dump without its unwritten last line.
    std::vector<std::string> warnings;
};

/// Parses a serial dump. `source` names it in messages. Throws
/// std::runtime_error "SOURCE:LINE: ..." (or "SOURCE: ...") for a missing
/// END, Count1/Count2 or dump, a value that is not a byte over 250, a dump
/// whose length disagrees with a printed addr (but for the missing last
/// line, a warning), or a second run.
RobotLog parse_robot_log(std::string_view text, const std::string& source);

/// Reads and parses a file (a missing or unreadable file is one line too).
RobotLog read_robot_log(const std::filesystem::path& path);

}  // namespace ddmr::calibrate
