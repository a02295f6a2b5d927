#pragma once
// A PlatformIO project as `pio run` leaves it (issue 24): which environment,
// which board (MCU and clock), and the ELF at
// <build_dir>/<env>/firmware.elf, refused when it is older than the
// project's sources.
//
// platformio.ini is read with libinih (Debian's libinih-dev): sections,
// `key = value`, values continued on indented lines, `;` and `#` comments.
// A value is looked up as PlatformIO does: the environment's own section
// [env:NAME], then the sections its `extends` names (in order, recursively),
// then the common [env] section. `${section.key}` and `${sysenv.NAME}` in a
// value are replaced; any other `${...}` is refused with one line.
// [platformio]: default_envs, workspace_dir (default .pio), build_dir
// (default <workspace_dir>/build), src_dir (src), include_dir (include),
// lib_dir (lib).
//
// The boards: PlatformIO's board IDs for the Arduino boards ddmr-hil
// models (hil/board_description.hpp): uno; nanoatmega328 and
// nanoatmega328new (nano); pro8MHzatmega328 (pro-mini-8mhz); megaatmega2560
// (mega2560). `board_build.f_cpu` and `board_build.mcu`, when set, must be
// the board's.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "hil/board_description.hpp"

namespace ddmr::tools {

struct PlatformioProject {
    std::filesystem::path dir;       ///< the project folder (holds platformio.ini)
    std::string env;                 ///< the environment used
    std::string board_id;            ///< PlatformIO's `board =`
    hil::BoardModel board = hil::BoardModel::uno;
    std::filesystem::path elf;       ///< <build_dir>/<env>/firmware.elf
    std::vector<std::filesystem::path> source_dirs;  ///< checked against the ELF's age
};

/// Reads DIR/platformio.ini and checks the environment, the board and the
/// ELF. `env` empty: the first of default_envs, else the only [env:NAME].
/// Throws std::invalid_argument with one line naming the file (and line),
/// the key or the ELF: no platformio.ini, an unknown environment, a board
/// ddmr-hil does not model, an f_cpu or mcu not the board's, no ELF (run
/// `pio run -e NAME`), an ELF older than a source file.
PlatformioProject load_platformio_project(const std::filesystem::path& dir, const std::string& env);

/// {"platformio": dir, "env", "board_id", "board", "elf"} for summary.json.
nlohmann::json platformio_json(const PlatformioProject& project);

/// The PlatformIO board ID -> ddmr-hil board, nullopt if not modelled.
std::optional<hil::BoardModel> platformio_board(const std::string& board_id);

}  // namespace ddmr::tools
