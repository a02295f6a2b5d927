#pragma once
// Atomic output files: write to a temporary file in the same folder, flush,
// then rename over the destination. An interrupted run never leaves a
// half-written file that looks complete.

#include <cstdio>
#include <filesystem>
#include <string_view>

namespace ddmr::tools {

/// Writes `content` to `path` atomically (temp file + fsync + rename).
/// Throws std::runtime_error naming the path and the OS error on failure.
void write_file_atomic(const std::filesystem::path& path, std::string_view content);

/// A file written progressively (streamed rows) that appears under its name
/// only when commit() succeeds: until then it is a temporary file beside it,
/// removed if the writer is destroyed uncommitted.
class AtomicFileWriter {
public:
    /// Opens the temporary file; throws std::runtime_error naming `path`.
    explicit AtomicFileWriter(std::filesystem::path path);
    ~AtomicFileWriter();
    AtomicFileWriter(const AtomicFileWriter&) = delete;
    AtomicFileWriter& operator=(const AtomicFileWriter&) = delete;

    /// Appends bytes (buffered). Never throws: a write error is kept and
    /// reported by commit(), so it can be called inside the simulation.
    void write(std::string_view bytes) noexcept;
    /// Flushes, syncs and renames over `path`. Throws std::runtime_error.
    void commit();
    const std::filesystem::path& path() const { return path_; }

private:
    std::filesystem::path path_;
    std::filesystem::path tmp_;
    std::FILE* file_ = nullptr;
    int error_ = 0;
    bool committed_ = false;
};

/// Checks that `dir` can be used as an output folder: it exists as a directory
/// or can be created, and is writable. Throws std::runtime_error otherwise.
/// Call it before a run so bad output folders fail up front.
void prepare_output_dir(const std::filesystem::path& dir);

/// Checks that `dir` could be made an output folder later without creating
/// anything now: it is a writable folder, or the nearest part of its path
/// that exists is. Throws std::runtime_error saying which part is wrong.
void check_output_dir(const std::filesystem::path& dir);

/// Checks that `file` can be written later without creating anything now:
/// its parent folder (the current one if it has none) exists, is a folder and
/// is writable, and `file` is not a folder. Throws std::runtime_error saying
/// which; write nothing before calling it.
void check_output_file(const std::filesystem::path& file);

}  // namespace ddmr::tools
