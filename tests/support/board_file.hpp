#pragma once
// A board file written to a temporary b.yaml and read as `--board` reads it,
// for the tests of the board file's form and its refusals.
#include <fstream>
#include <stdexcept>
#include <string>

#include "hil/board.hpp"
#include "support/temp_dir.hpp"

namespace ddmr::test {

/// The error reading `yaml` as a board file gives, or "" when it loads.
inline std::string board_load_error(const std::string& yaml) {
    TempDir dir;
    std::ofstream(dir / "b.yaml") << yaml;
    try {
        (void)hil::load_board_file(dir / "b.yaml");
    } catch (const std::runtime_error& e) {
        return e.what();
    }
    return "";
}

/// The `wheels:` of the parts' test boards: dir-pwm on D10..D13, single
/// encoders on D2 and D3.
inline const std::string kUnoTestWheels =
    "wheels:\n"
    "  right: {motor: {driver: dir-pwm, PWM: 10, DIR: 12}, encoder: {type: single, OUT: 2}}\n"
    "  left:  {motor: {driver: dir-pwm, PWM: 11, DIR: 13}, encoder: {type: single, OUT: 3}}\n";

/// An Uno board file with `parts` (YAML list items, each "  - {...}\n") and
/// kUnoTestWheels, read back.
inline hil::BoardWiring uno_with_parts(const TempDir& dir, const std::string& parts) {
    std::ofstream(dir / "b.yaml") << "board: uno\nparts:\n" << parts << kUnoTestWheels;
    return hil::load_board_file(dir / "b.yaml");
}

}  // namespace ddmr::test
