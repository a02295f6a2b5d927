#include "common/source_lines.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>
#include <stdexcept>

#include "common/spawn.hpp"

namespace ddmr::tools {

namespace fs = std::filesystem;

fs::path addr2line_program() {
    const char* path = std::getenv("PATH");
    std::stringstream dirs(path != nullptr ? path : "/usr/bin:/bin");
    std::string dir;
    while (std::getline(dirs, dir, ':')) {
        if (dir.empty()) continue;
        fs::path p = fs::path(dir) / "avr-addr2line";  // not const: returned by move
        if (::access(p.c_str(), X_OK) == 0) return p;
    }
    return {};
}

std::map<uint32_t, std::string> source_lines(const fs::path& elf, const std::vector<uint32_t>& pcs) {
    std::map<uint32_t, std::string> out;
    const std::set<uint32_t> unique(pcs.begin(), pcs.end());
    if (unique.empty()) return out;
    const fs::path program = addr2line_program();
    if (program.empty()) {
        throw std::runtime_error("avr-addr2line (Debian package binutils-avr) is not on PATH: install it for source lines");
    }
    std::vector<std::string> args = {program.string(), "-e", elf.string()};
    for (const uint32_t pc : unique) args.push_back(fmt::format("0x{:x}", pc));
    const fs::path tmp = fs::temp_directory_path() / fmt::format("ddmr-hil-addr2line-{}.txt", ::getpid());
    pid_t pid = 0;
    if (spawn_redirected(std::move(args), tmp, tmp, pid) != 0) {
        throw std::runtime_error("cannot start " + program.string());
    }
    int status = 0;
    ::waitpid(pid, &status, 0);
    std::ifstream in(tmp);
    std::vector<std::string> lines;
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    in.close();
    std::error_code ignored;
    fs::remove(tmp, ignored);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || lines.size() != unique.size()) {
        throw std::runtime_error(fmt::format("avr-addr2line failed on {}: {}", elf.string(),
                                             lines.empty() ? std::string("no output") : lines.front()));
    }
    auto it = unique.begin();
    for (const std::string& line : lines) {
        const uint32_t pc = *it++;
        // "??:0" / "??:?" / "file:?": no line information.
        if (line.rfind("??", 0) == 0 || line.size() < 2 || line.substr(line.size() - 2) == ":?" ||
            line.substr(line.size() - 2) == ":0") {
            continue;
        }
        // "file:line (discriminator N)"
        out[pc] = line.substr(0, line.find(" ("));
    }
    return out;
}

}  // namespace ddmr::tools
