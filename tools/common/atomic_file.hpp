#pragma once
// Atomic output files: write to a temporary file in the same folder, flush,
// then rename over the destination. An interrupted run never leaves a
// half-written file that looks complete.

#include <filesystem>
#include <string_view>

namespace ddmr::tools {

/// Writes `content` to `path` atomically (temp file + fsync + rename).
/// Throws std::runtime_error naming the path and the OS error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// Checks that `dir` can be used as an output folder: it exists as a directory
/// or can be created, and is writable. Throws std::runtime_error otherwise.
/// Call it before a run so bad output folders fail up front.
void prepare_output_dir(const std::filesystem::path& dir);

}  // namespace ddmr::tools
