#pragma once
// Builds an Arduino sketch named by a scenario (`firmware: {sketch: x/x.ino}`)
// into an ELF, the way the project builds the reference sketch
// (cmake/ArduinoSketch.cmake: Debian's arduino-builder, the Uno, the same
// preference), and caches the result by the sketch's content.
//
// The cache folder holds one sub-folder per SHA-256 of the .ino, board
// (FQBN) and sketch name; a build goes
// to a temporary folder first and is renamed into place, so parallel workers
// and interrupted builds never see half an ELF. arduino-builder runs without
// a shell (posix_spawn); its output goes to build.log in the cache entry.

#include <filesystem>
#include <string>

namespace ddmr::tools::scenario {

/// The default cache: $XDG_CACHE_HOME/ddmr-hil/sketches, else
/// $HOME/.cache/ddmr-hil/sketches, else /tmp/ddmr-hil-sketches.
std::filesystem::path default_sketch_cache();

/// The ELF of `ino` (built now or taken from `cache`). Throws
/// std::runtime_error naming the sketch: not a .ino, its folder not named
/// after it (Arduino's rule), or the build failed (with the log's path).
/// `fqbn`: the board to build for (BoardDescription::fqbn).
std::filesystem::path build_sketch(const std::filesystem::path& ino, const std::filesystem::path& cache,
                                   const std::string& fqbn);

}  // namespace ddmr::tools::scenario
