#include "common/sketch_build.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/atomic_file.hpp"
#include "common/sha256.hpp"
#include "common/spawn.hpp"
#include "common/visible_files.hpp"
#include "hil/zero_calls.hpp"

namespace ddmr::tools {
namespace fs = std::filesystem;
using nlohmann::json;

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

std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

/// Every regular file under `dir` (dot-names skipped: .git, editor files),
/// relative names and contents, in name order: the folder's identity.
void hash_folder(Sha256& h, const fs::path& dir) {
    for (const auto& f : visible_files(dir)) {
        h.update(f.generic_string());
        h.update(std::string_view("\0", 1));
        h.update(std::to_string(fs::file_size(dir / f)));
        h.update(std::string_view("\0", 1));
        h.update_file(dir / f);
    }
}

std::string folder_sha256(const fs::path& dir) {
    Sha256 h;
    hash_folder(h, dir);
    return h.hex();
}

/// The arduino-builder command line (the one cmake/ArduinoSketch.cmake runs,
/// plus -verbose for its "Using library" lines, and the libraries folders).
std::vector<std::string> builder_args(const fs::path& ino, const fs::path& build_dir, const std::string& fqbn,
                                      const std::vector<fs::path>& libraries) {
    std::vector<std::string> args = {DDMR_ARDUINO_BUILDER, "-compile", "-verbose"};
    std::stringstream dirs(DDMR_ARDUINO_HARDWARE_DIRS);
    for (std::string dir; std::getline(dirs, dir, ':');) args.insert(args.end(), {"-hardware", dir});
    args.insert(args.end(), {"-tools", DDMR_ARDUINO_TOOLS_DIR, "-fqbn", fqbn});
    // arduino-builder prefers the folder given last: the most preferred goes last.
    for (auto lib = libraries.rbegin(); lib != libraries.rend(); ++lib) {
        args.insert(args.end(), {"-libraries", lib->string()});
    }
    // -prefs before the sketch: arduino-builder ignores options after it.
    args.insert(args.end(), {"-build-path", build_dir.string(),
                             std::string("-prefs=") + DDMR_ARDUINO_EXTRA_PREFS, fs::absolute(ino).string()});
    return args;
}

bool is_under(const fs::path& p, const fs::path& dir) {
    const std::string rel = p.lexically_normal().lexically_relative(dir.lexically_normal()).generic_string();
    return !rel.empty() && rel != "." && rel.rfind("..", 0) != 0;
}

/// A copy of the sketch's folder without the src/ sub-folders arduino-builder
/// used as libraries (so they are compiled once, as libraries).
fs::path stage_without(const fs::path& ino, const std::vector<fs::path>& skip, const fs::path& stage_root) {
    const fs::path src_dir = ino.parent_path();
    const fs::path dest = stage_root / src_dir.filename();
    fs::create_directories(dest);
    for (auto it = fs::recursive_directory_iterator(src_dir); it != fs::recursive_directory_iterator(); ++it) {
        const fs::path& p = it->path();
        const bool skipped = std::any_of(skip.begin(), skip.end(), [&](const fs::path& s) { return p == s; });
        if (skipped) {
            if (it->is_directory()) it.disable_recursion_pending();
            continue;
        }
        const fs::path to = dest / p.lexically_relative(src_dir);
        if (it->is_directory()) {
            fs::create_directories(to);
        } else if (it->is_regular_file()) {
            fs::copy_file(p, to);
        }
    }
    return dest / ino.filename();
}

std::string display(const fs::path& p) {
    std::error_code ec;
    const fs::path rel = p.lexically_proximate(fs::current_path(ec));
    return (ec || rel.empty() || rel.generic_string().rfind("../../", 0) == 0) ? p.string() : rel.string();
}

std::string folder_list(const LibraryFolders& folders) {
    std::string s = "the Arduino core's libraries";
    for (const auto& f : folders.searched) {
        s += ", " + f.string();
        if (!fs::is_directory(f)) s += " (no such folder)";
    }
    return s;
}

json libraries_json(const std::vector<UsedLibrary>& used, bool with_hash) {
    json a = json::array();
    for (const auto& u : used) {
        json l = {{"name", u.name}, {"version", u.version}, {"folder", u.folder.string()}};
        if (with_hash) l["sha256"] = fs::is_directory(u.folder) ? folder_sha256(u.folder) : "";
        a.push_back(std::move(l));
    }
    return a;
}

/// The cached entry's libraries and warnings if every library is unchanged, else nullopt.
std::optional<std::pair<std::vector<UsedLibrary>, std::vector<std::string>>> valid_entry(const fs::path& entry,
                                                                                        const fs::path& elf) {
    if (!fs::is_regular_file(elf) || !fs::is_regular_file(entry / "libraries.json")) return std::nullopt;
    try {
        const json j = json::parse(read_text(entry / "libraries.json"));
        std::vector<UsedLibrary> used;
        for (const auto& l : j.at("libraries")) {
            UsedLibrary u{l.at("name").get<std::string>(), l.at("version").get<std::string>(),
                          fs::path(l.at("folder").get<std::string>())};
            if (!fs::is_directory(u.folder) || folder_sha256(u.folder) != l.at("sha256").get<std::string>()) {
                return std::nullopt;
            }
            used.push_back(std::move(u));
        }
        return std::pair{std::move(used), j.at("warnings").get<std::vector<std::string>>()};
    } catch (const std::exception&) {
        return std::nullopt;  // an unreadable entry is built again
    }
}

/// The ELF's unguarded calls to address 0 (hil/zero_calls.hpp), after
/// arduino-builder's own warnings: found on every build, cached or not.
void add_zero_call_warnings(SketchBuild& b) {
    for (std::string& line : hil::describe_zero_calls(hil::find_zero_calls(hil::ElfImage::read(b.elf)))) {
        b.warnings.push_back(std::move(line));
    }
}

}  // namespace

fs::path sketch_ino(const fs::path& sketch, const std::string& what) {
    if (!fs::is_directory(sketch)) return sketch;
    const fs::path folder = sketch.filename().empty() ? sketch.parent_path() : sketch;
    fs::path ino = folder / (folder.filename().string() + ".ino");
    if (!fs::is_regular_file(ino)) {
        throw std::invalid_argument(fmt::format("{} {}: a folder without {} (a sketch folder holds the .ino of its name)",
                                                what, sketch.string(), ino.filename().string()));
    }
    return ino;
}

SketchBuild build_sketch(const fs::path& ino, const SketchBuildOptions& options) {
    if (ino.extension() != ".ino") throw SketchBuildError(fmt::format("sketch {}: not a .ino file", ino.string()));
    if (!fs::is_regular_file(ino)) throw SketchBuildError(fmt::format("sketch {}: no such file", ino.string()));
    const std::string stem = ino.stem().string();
    if (fs::absolute(ino).parent_path().filename() != stem) {
        throw SketchBuildError(fmt::format("sketch {}: Arduino needs it in a folder of the same name ({}/{}.ino)",
                                           ino.string(), stem, stem));
    }
    SketchBuild b;
    b.sketch = ino;
    b.folders = library_folders(ino, options.libraries);

    // The cache key: board, name, the sketch folder's files, the library folders.
    Sha256 key;
    key.update(options.fqbn + '\n' + stem + '\n');
    hash_folder(key, fs::absolute(ino).parent_path());
    for (const auto& dir : b.folders.existing) {
        // The folder and the libraries in it: one installed since is another build.
        key.update("-libraries " + dir.string() + '\n');
        std::vector<std::string> names;
        for (const auto& e : fs::directory_iterator(dir)) {
            if (e.is_directory()) names.push_back(e.path().filename().string());
        }
        std::sort(names.begin(), names.end());
        for (const auto& n : names) key.update("  " + n + '\n');
    }
    std::string board = options.fqbn;
    std::replace_if(board.begin(), board.end(), [](char c) { return c == ':' || c == '=' || c == ','; }, '_');
    const fs::path entry = options.cache / (key.hex() + "-" + board + "-" + stem);
    b.elf = entry / (stem + ".elf");
    b.log = entry / "build.log";
    if (auto cached = valid_entry(entry, b.elf)) {
        b.libraries = std::move(cached->first);
        b.warnings = std::move(cached->second);
        b.from_cache = true;
        add_zero_call_warnings(b);
        return b;
    }

    fs::create_directories(options.cache);
    const fs::path work = options.cache / fmt::format("tmp-{}-{}", stem, ::getpid());
    fs::remove_all(work);
    fs::create_directories(work / "build");
    const fs::path abs_ino = fs::absolute(ino);
    int rc = run_logged(builder_args(abs_ino, work / "build", options.fqbn, b.folders.existing), work / "build.log");
    std::string log = read_text(work / "build.log");
    fs::path built = work / "build" / (stem + ".ino.elf");
    b.libraries = parse_used_libraries(log);
    // A library in the sketch's src/ was compiled twice (as a library and as
    // sketch code): build once more without it in the sketch.
    const fs::path own_src = abs_ino.parent_path() / "src";
    std::vector<fs::path> in_src;
    for (const auto& u : b.libraries) {
        if (is_under(u.folder, own_src)) in_src.push_back(u.folder.lexically_normal());
    }
    fs::path staged_dir;
    if ((rc != 0 || !fs::is_regular_file(built)) && !in_src.empty()) {
        const fs::path staged = stage_without(abs_ino, in_src, work / "stage");
        staged_dir = staged.parent_path();
        fs::remove_all(work / "build");
        fs::create_directories(work / "build");
        rc = run_logged(builder_args(staged, work / "build", options.fqbn, b.folders.existing), work / "build.log");
        log = read_text(work / "build.log");
        b.libraries = parse_used_libraries(log);
    }
    b.warnings = builder_warnings(log);
    // A path in the staged copy, as the user knows it.
    const auto users_path = [&](fs::path file) {
        if (!staged_dir.empty() && is_under(file, staged_dir)) {
            file = abs_ino.parent_path() / file.lexically_relative(staged_dir);
        }
        return file.lexically_normal() == abs_ino.lexically_normal() ? ino.string() : display(file);
    };
    if (rc != 0 || !fs::is_regular_file(built)) {
        const fs::path kept = options.cache / fmt::format("failed-{}.log", stem);
        fs::copy_file(work / "build.log", kept, fs::copy_options::overwrite_existing);
        fs::remove_all(work);
        if (const auto missing = find_missing_header(log)) {
            const auto book = sketchbook_libraries();
            // The sketch as the user named it; another file (a library's) as the compiler did.
            throw SketchBuildError(fmt::format(
                "{}:{}: '{}' not found in {}; install the library into {} or {}", users_path(missing->file),
                missing->line, missing->header, folder_list(b.folders),
                book ? book->string() : std::string("~/Arduino/libraries"), options.more_libraries_advice));
        }
        // The compiler's (or linker's) first error, its file as the user knows it.
        std::string first;
        if (auto error = first_build_error(log)) {
            static const std::regex located(R"(^(.+?)(:[0-9]+:.*)$)");
            std::smatch m;
            first = std::regex_match(*error, m, located) ? users_path(m[1].str()) + m[2].str() : *error;
            first = ": " + first;
        }
        throw SketchBuildError(fmt::format("sketch {}: arduino-builder failed (exit {}){}; its whole output: {}",
                                           ino.string(), rc, first, kept.string()));
    }
    fs::create_directories(work / "entry");
    fs::copy_file(built, work / "entry" / (stem + ".elf"));
    fs::copy_file(work / "build.log", work / "entry" / "build.log");
    write_file_atomic(work / "entry" / "libraries.json",
                      json{{"libraries", libraries_json(b.libraries, true)}, {"warnings", b.warnings}}.dump(2) + "\n");
    std::error_code ec;
    fs::remove_all(entry, ec);  // a stale entry (its libraries changed)
    fs::rename(work / "entry", entry, ec);  // another worker may have won the race: its ELF is the same
    fs::remove_all(work);
    if (!fs::is_regular_file(b.elf)) {
        throw std::runtime_error(fmt::format("sketch {}: cache {} unusable", ino.string(), entry.string()));
    }
    add_zero_call_warnings(b);
    return b;
}

json sketch_build_json(const SketchBuild& build) {
    json folders = json::array();
    for (const auto& f : build.folders.searched) {
        folders.push_back({{"folder", f.string()}, {"exists", fs::is_directory(f)}});
    }
    return {{"sketch", build.sketch.string()},       {"elf", build.elf.string()},
            {"from_cache", build.from_cache},         {"build_log", build.log.string()},
            {"library_folders", std::move(folders)}, {"libraries", libraries_json(build.libraries, false)},
            {"warnings", build.warnings}};
}

std::string describe_libraries(const SketchBuild& build) {
    std::string s = fmt::format("sketch {}: ", build.sketch.string());
    if (build.libraries.empty()) s += "no libraries";
    for (std::size_t i = 0; i < build.libraries.size(); ++i) {
        const auto& u = build.libraries[i];
        s += i > 0 ? ", " : (build.libraries.size() == 1 ? "library " : "libraries ");
        s += u.version.empty() ? fmt::format("{} (legacy, {})", u.name, u.folder.string())
                               : fmt::format("{} {} ({})", u.name, u.version, u.folder.string());
    }
    for (const auto& w : build.warnings) s += fmt::format("\nsketch {}: warning: {}", build.sketch.string(), w);
    return s;
}

}  // namespace ddmr::tools
