#pragma once
// The rig configuration of an example robot in firmware/examples/NAME: its
// board.yaml's board and wiring, the default plant.
#include <string>

#include "hil/board.hpp"
#include "hil/robot_rig.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {

inline hil::RigConfig example_rig(const std::string& example) {
    hil::RigConfig c;
    c.board = hil::load_board_file(source_dir() / "firmware/examples" / example / "board.yaml");
    return c;
}

}  // namespace ddmr::test
