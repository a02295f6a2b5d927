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

}  // namespace ddmr::test
