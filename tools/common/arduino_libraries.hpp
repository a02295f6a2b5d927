#pragma once
// Where an Arduino sketch's libraries are looked for, and what
// arduino-builder said about them (issue 24).
//
// The folders, by precedence: when two hold a library for the same header,
// the first one's is used (arduino-builder prefers the `-libraries` folder
// given last, so they are given in the reverse order):
//   1. the sketch's own `src/` (Arduino's convention for code shipped with a
//      sketch: a library copied into `<sketch>/src/<Lib>/`);
//   2. the folders the user names (`--libraries DIR`, a scenario's
//      `libraries: [DIR, ...]`), in their order; each must exist;
//   3. the sketchbook's `libraries/`: `$ARDUINO_DIRECTORIES_USER/libraries`
//      when that is set (arduino-cli's setting), else `~/Arduino/libraries`
//      (the Arduino IDE's and arduino-cli's default).
// Folders 1 and 3 are passed only when they exist (arduino-builder aborts on
// a `-libraries` folder that does not exist). arduino-builder itself resolves
// each #include to a library in them (library.properties, architectures,
// the src/ and flat layouts): nothing here resolves libraries.
//
// What it says is recognised in its log: `Using library NAME at version V in
// folder: DIR` (or `... in folder: DIR (legacy)` for a library without
// library.properties), printed with -verbose; and avr-gcc's
// `FILE:LINE:COL: fatal error: HEADER: No such file or directory`.

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace ddmr::tools {

/// The libraries folders for a sketch.
struct LibraryFolders {
    std::vector<std::filesystem::path> searched;  ///< every candidate, in order (for messages)
    std::vector<std::filesystem::path> existing;  ///< those passed to arduino-builder
};

/// The sketchbook's libraries folder: $ARDUINO_DIRECTORIES_USER/libraries,
/// else $HOME/Arduino/libraries; nullopt without either variable.
std::optional<std::filesystem::path> sketchbook_libraries();

/// Why `dir` looks like one library rather than a folder of libraries ("it
/// has library.properties", "it has X.h at its top": the legacy flat
/// layout), or nullopt.
std::optional<std::string> library_itself(const std::filesystem::path& dir);

/// The folders for `ino` with the user's `named` folders (absolute or
/// relative to the working directory). Throws std::invalid_argument
/// "--libraries DIR: no such folder" for a named folder that is not a folder,
/// and "--libraries DIR: a library itself ..." for one that is a library
/// (library.properties, or sources at its top) rather than a folder of them.
LibraryFolders library_folders(const std::filesystem::path& ino, const std::vector<std::filesystem::path>& named);

/// A library arduino-builder used.
struct UsedLibrary {
    std::string name;
    std::string version;  ///< empty for a legacy library (no library.properties)
    std::filesystem::path folder;
};

/// Every `Using library ...` line of an arduino-builder -verbose log, in order.
std::vector<UsedLibrary> parse_used_libraries(const std::string& log);

/// avr-gcc's `FILE:LINE:COL: fatal error: HEADER: No such file or directory`.
struct MissingHeader {
    std::filesystem::path file;
    int line = 0;
    std::string header;
};

/// The first missing header the compiler reported in `log`, if any.
std::optional<MissingHeader> find_missing_header(const std::string& log);

/// What arduino-builder warns about in `log`, one line each: a header found
/// in several libraries ("'Lib.h' is in 2 libraries: used /a/Lib, not used
/// /b/Lib"), a library that claims other architectures (its own WARNING line).
std::vector<std::string> builder_warnings(const std::string& log);

/// The first compiler or linker error of `log` ("FILE:LINE:COL: error: ...",
/// "... undefined reference to ...", "... multiple definition of ..."), if any.
std::optional<std::string> first_build_error(const std::string& log);

}  // namespace ddmr::tools
