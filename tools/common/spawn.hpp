#pragma once
// Starting a program without a shell, its output into files (posix_spawn).
#include <sys/types.h>

#include <filesystem>
#include <string>
#include <vector>

namespace ddmr::tools {

/// Starts `args[0]` (a path, no PATH search) with `args` as its argv and this
/// process's environment, stdout truncated into `stdout_file` and stderr into
/// `stderr_file` (the same path: both into one file, in order). Sets `pid` and
/// returns 0, or returns posix_spawn's error number. The caller waits.
int spawn_redirected(std::vector<std::string> args, const std::filesystem::path& stdout_file,
                     const std::filesystem::path& stderr_file, pid_t& pid);

/// Starts `args[0]` (a path, no PATH search) with `args` as its argv, this
/// process's environment and its stdin, stdout and stderr. Sets `pid` and
/// returns 0, or returns posix_spawn's error number. The caller waits.
int spawn_inherit(std::vector<std::string> args, pid_t& pid);

}  // namespace ddmr::tools
