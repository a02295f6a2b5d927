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

namespace {

/// "file:line" or "file:line (discriminator N)"; false for "??:0", "??:?",
/// "file:?" and "file:0" (no line information).
bool parse_file_line(const std::string& text, std::string& file, uint32_t& line) {
    const std::string location = text.substr(0, text.find(" ("));
    const std::size_t colon = location.rfind(':');
    if (colon == std::string::npos || location.rfind("??", 0) == 0) return false;
    const std::string number = location.substr(colon + 1);
    if (number.empty() || number.find_first_not_of("0123456789") != std::string::npos) return false;
    line = static_cast<uint32_t>(std::stoul(number));
    file = location.substr(0, colon);
    return line != 0;
}

}  // namespace

std::map<uint32_t, SourceLocation> source_locations(const fs::path& elf, const std::vector<uint32_t>& pcs) {
    std::map<uint32_t, SourceLocation> out;
    const std::set<uint32_t> unique(pcs.begin(), pcs.end());
    if (unique.empty()) return out;
    const fs::path program = addr2line_program();
    if (program.empty()) {
        throw std::runtime_error("avr-addr2line (Debian package binutils-avr) is not on PATH: install it for source lines");
    }
    // -a: each address first (0x...), then -i's function/location pairs,
    // innermost inlined code first, the outermost function last.
    std::vector<std::string> args = {program.string(), "-a", "-f", "-i", "-e", elf.string()};
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
    // Blocks: "0x<address>", then (function, location) pairs.
    std::vector<std::size_t> starts;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].rfind("0x", 0) == 0) starts.push_back(i);
    }
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || starts.size() != unique.size()) {
        throw std::runtime_error(fmt::format("avr-addr2line failed on {}: {}", elf.string(),
                                             lines.empty() ? std::string("no output") : lines.front()));
    }
    auto it = unique.begin();
    for (std::size_t b = 0; b < starts.size(); ++b, ++it) {
        const std::size_t first = starts[b] + 1;
        const std::size_t last = b + 1 < starts.size() ? starts[b + 1] : lines.size();
        if (last < first + 2 || (last - first) % 2 != 0) continue;
        SourceLocation loc;
        if (!parse_file_line(lines[first + 1], loc.file, loc.line)) continue;
        loc.function = lines[last - 2];  // the last pair's function
        out[*it] = std::move(loc);
    }
    return out;
}

std::map<uint32_t, std::string> source_lines(const fs::path& elf, const std::vector<uint32_t>& pcs) {
    std::map<uint32_t, std::string> out;
    for (const auto& [pc, loc] : source_locations(elf, pcs)) out[pc] = fmt::format("{}:{}", loc.file, loc.line);
    return out;
}

}  // namespace ddmr::tools
