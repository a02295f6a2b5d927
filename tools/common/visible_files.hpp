#pragma once
// The files of a folder a person keeps there: every regular file below it,
// without the names that start with '.' (.git, .pio, editor files) and what
// is under them. The sketch cache's key and a PlatformIO project's source
// age are both taken over these.
#include <filesystem>
#include <vector>

namespace ddmr::tools {

/// Relative to `dir`, in name order (deterministic whatever the file system's order).
std::vector<std::filesystem::path> visible_files(const std::filesystem::path& dir);

}  // namespace ddmr::tools
