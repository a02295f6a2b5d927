#pragma once
// Builds an Arduino sketch (`firmware: {sketch: x/x.ino}` in a scenario,
// `run --sketch x/x.ino`) into an ELF the way the project builds the
// reference sketch (cmake/ArduinoSketch.cmake: Debian's arduino-builder, the
// same hardware and tools folders, the same preference), with the library
// folders of common/arduino_libraries.hpp, and caches the result.
//
// The cache holds one folder per SHA-256 of the board (FQBN), the sketch's
// name, every file of the sketch's folder (its .ino, .cpp, .h and src/,
// names and contents), the library folders given to arduino-builder and the
// names of the libraries in them.
// Beside the ELF it keeps build.log (arduino-builder -verbose) and
// libraries.json (the libraries arduino-builder used, each with a SHA-256 of
// its folder): an entry whose libraries changed since is built again. A
// build goes to a temporary folder first and is renamed into place, so
// parallel workers and interrupted builds never see half an ELF.
// arduino-builder runs without a shell (posix_spawn).
//
// A library shipped in the sketch's src/ (`<sketch>/src/<Lib>/`) is found
// through the src/ folder given as a libraries folder; arduino-builder also
// compiles src/ as the sketch's own code, which defines the library twice.
// When a first build fails having used such a library, the sketch is built
// again from a copy of its folder without those libraries' folders.

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/arduino_libraries.hpp"

namespace ddmr::tools {

/// The default cache: $XDG_CACHE_HOME/ddmr-hil/sketches, else
/// $HOME/.cache/ddmr-hil/sketches, else /tmp/ddmr-hil-sketches.
std::filesystem::path default_sketch_cache();

struct SketchBuildOptions {
    std::string fqbn;                               ///< the board (BoardDescription::fqbn)
    std::vector<std::filesystem::path> libraries;   ///< the user's library folders (--libraries)
    /// The end of the missing-library line, after "install the library into ~/Arduino/libraries or ".
    std::string more_libraries_advice = "pass --libraries DIR";
    std::filesystem::path cache = default_sketch_cache();
};

struct SketchBuild {
    std::filesystem::path sketch;       ///< the .ino
    std::filesystem::path elf;          ///< in the cache
    std::filesystem::path log;          ///< arduino-builder's output (build.log in the cache entry)
    LibraryFolders folders;             ///< where libraries were looked for
    std::vector<UsedLibrary> libraries; ///< what arduino-builder used
    /// arduino-builder's (common/arduino_libraries.hpp builder_warnings), then
    /// the ELF's unguarded calls to address 0 (hil/zero_calls.hpp)
    std::vector<std::string> warnings;
    bool from_cache = false;
};

/// The sketch's build failed in a way that is the input's fault (a missing
/// library, a compile error): one line, exit 2.
class SketchBuildError : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

/// The .ino a sketch argument names: the file itself, or for a folder x/
/// its x/x.ino (as arduino-cli takes it). Throws std::invalid_argument
/// "`what` ARG: a folder without x.ino ..." when the folder has none.
std::filesystem::path sketch_ino(const std::filesystem::path& sketch, const std::string& what);

/// The ELF of `ino`, built now or taken from the cache. Throws
/// SketchBuildError naming the sketch: not a .ino, its folder not named after
/// it (Arduino's rule), a header no library folder has (`FILE:LINE: 'X.h'
/// not found in ...; install the library into ~/Arduino/libraries or pass
/// --libraries DIR`), any other build failure (its first compiler or linker
/// error, and the log's path);
/// std::invalid_argument for a named library folder that does not exist.
SketchBuild build_sketch(const std::filesystem::path& ino, const SketchBuildOptions& options);

/// {"sketch", "elf", "from_cache", "build_log", "library_folders": [...],
///  "libraries": [{"name", "version", "folder"}]} for summary.json / result.json.
nlohmann::json sketch_build_json(const SketchBuild& build);

/// For the console: "sketch x/x.ino: libraries Servo 1.1.8
/// (/root/Arduino/libraries/Servo), Foo (legacy, /l/Foo)" or "... no
/// libraries", then a line "sketch x/x.ino: warning: ..." per warning.
std::string describe_libraries(const SketchBuild& build);

}  // namespace ddmr::tools
