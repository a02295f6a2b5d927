#include "scenario/sketch_build.hpp"

#include <sys/wait.h>

#include <algorithm>
#include <fmt/format.h>

#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/sha256.hpp"
#include "common/spawn.hpp"

namespace ddmr::tools::scenario {
namespace fs = std::filesystem;

fs::path default_sketch_cache() {
    if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
        return fs::path(xdg) / "ddmr-hil" / "sketches";
    }
    if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
        return fs::path(home) / ".cache" / "ddmr-hil" / "sketches";
    }
    return "/tmp/ddmr-hil-sketches";
}

namespace {

/// Runs `args` (no shell) with stdout and stderr into `log`; its exit status.
int run_logged(std::vector<std::string> args, const fs::path& log) {
    pid_t pid = 0;
    if (spawn_redirected(std::move(args), log, log, pid) != 0) return -1;
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

fs::path build_sketch(const fs::path& ino, const fs::path& cache, const std::string& fqbn) {
    if (ino.extension() != ".ino") throw std::runtime_error(fmt::format("sketch {}: not a .ino file", ino.string()));
    if (!fs::is_regular_file(ino)) throw std::runtime_error(fmt::format("sketch {}: no such file", ino.string()));
    const std::string stem = ino.stem().string();
    if (ino.parent_path().filename() != stem) {
        throw std::runtime_error(fmt::format("sketch {}: Arduino needs it in a folder of the same name ({}/{}.ino)",
                                             ino.string(), stem, stem));
    }
    // One entry per sketch content and board (the same .ino built for the Nano is another ELF) ...
    std::string board = fqbn;
    std::replace_if(board.begin(), board.end(), [](char c) { return c == ':' || c == '=' || c == ','; }, '_');
    // ... and per name: the ELF is named after the sketch, and two folders may hold the same text.
    const fs::path entry = cache / (sha256_file_hex(ino) + "-" + board + "-" + stem);
    fs::path elf = entry / (stem + ".elf");  // not const: returned by move
    if (fs::is_regular_file(elf)) return elf;

    fs::create_directories(cache);
    const fs::path work = cache / fmt::format("tmp-{}-{}", stem, ::getpid());
    fs::remove_all(work);
    fs::create_directories(work / "build");
    std::vector<std::string> args = {DDMR_ARDUINO_BUILDER, "-compile"};
    std::stringstream dirs(DDMR_ARDUINO_HARDWARE_DIRS);
    for (std::string dir; std::getline(dirs, dir, ':');) args.insert(args.end(), {"-hardware", dir});
    args.insert(args.end(), {"-tools", DDMR_ARDUINO_TOOLS_DIR, "-fqbn", fqbn, "-build-path",
                             (work / "build").string(), std::string("-prefs=") + DDMR_ARDUINO_EXTRA_PREFS,
                             fs::absolute(ino).string()});
    const int rc = run_logged(args, work / "build.log");
    const fs::path built = work / "build" / (stem + ".ino.elf");
    if (rc != 0 || !fs::is_regular_file(built)) {
        const fs::path kept = cache / fmt::format("failed-{}.log", stem);
        fs::copy_file(work / "build.log", kept, fs::copy_options::overwrite_existing);
        fs::remove_all(work);
        throw std::runtime_error(fmt::format("sketch {}: arduino-builder failed (exit {}); its output: {}",
                                             ino.string(), rc, kept.string()));
    }
    fs::create_directories(work / "entry");
    fs::copy_file(built, work / "entry" / (stem + ".elf"));
    fs::copy_file(work / "build.log", work / "entry" / "build.log");
    std::error_code ec;
    fs::rename(work / "entry", entry, ec);  // another worker may have won the race: its ELF is the same
    fs::remove_all(work);
    if (!fs::is_regular_file(elf)) throw std::runtime_error(fmt::format("sketch {}: cache {} unusable", ino.string(), entry.string()));
    return elf;
}

}  // namespace ddmr::tools::scenario
