#include "common/spawn.hpp"

#include <fcntl.h>
#include <spawn.h>

extern char** environ;

namespace ddmr::tools {

int spawn_redirected(std::vector<std::string> args, const std::filesystem::path& stdout_file,
                     const std::filesystem::path& stderr_file, pid_t& pid) {
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    posix_spawn_file_actions_t actions;
    posix_spawn_file_actions_init(&actions);
    const std::string out_path = stdout_file.string();
    const std::string err_path = stderr_file.string();
    posix_spawn_file_actions_addopen(&actions, 1, out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (stderr_file == stdout_file) {
        posix_spawn_file_actions_adddup2(&actions, 1, 2);
    } else {
        posix_spawn_file_actions_addopen(&actions, 2, err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    }
    const int rc = posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ);
    posix_spawn_file_actions_destroy(&actions);
    return rc;
}

int spawn_inherit(std::vector<std::string> args, pid_t& pid) {
    std::vector<char*> argv;
    argv.reserve(args.size() + 1);
    for (auto& a : args) argv.push_back(a.data());
    argv.push_back(nullptr);
    return posix_spawn(&pid, argv[0], nullptr, nullptr, argv.data(), environ);
}

}  // namespace ddmr::tools
