#pragma once
// Process exit codes of ddmr-hil, shared by every subcommand.
namespace ddmr::tools {

inline constexpr int kExitOk = 0;           ///< success, every check passed
inline constexpr int kExitCheckFailed = 1;  ///< ran, but a check or tolerance failed
inline constexpr int kExitBadInput = 2;     ///< bad input or configuration: nothing ran
inline constexpr int kExitFirmware = 3;     ///< the firmware misbehaved (crash, timeout)

}  // namespace ddmr::tools
