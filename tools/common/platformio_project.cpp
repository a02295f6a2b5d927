#include "common/platformio_project.hpp"

#include <ini.h>

#include "common/visible_files.hpp"
#include "hil/elf_image.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <stdexcept>

namespace ddmr::tools {
namespace fs = std::filesystem;

namespace {

/// platformio.ini as sections of keys (values with continuation lines
/// joined by '\n', as libinih gives them).
struct Ini {
    fs::path file;
    std::vector<std::string> order;  ///< section names in file order
    std::map<std::string, std::map<std::string, std::string>> sections;

    [[nodiscard]] const std::string* find(const std::string& section, const std::string& key) const {
        const auto s = sections.find(section);
        if (s == sections.end()) return nullptr;
        const auto k = s->second.find(key);
        return k == s->second.end() ? nullptr : &k->second;
    }
};

int on_entry(void* user, const char* section, const char* name, const char* value) {
    auto& ini = *static_cast<Ini*>(user);
    if (ini.sections.find(section) == ini.sections.end()) ini.order.emplace_back(section);
    std::string& v = ini.sections[section][name];
    v = v.empty() ? std::string(value) : v + "\n" + value;  // inih hands continuation lines one by one
    return 1;
}

Ini read_ini(const fs::path& file) {
    Ini ini;
    ini.file = file;
    const int rc = ini_parse(file.c_str(), on_entry, &ini);
    if (rc < 0) throw std::invalid_argument(fmt::format("{}: cannot be read", file.string()));
    if (rc > 0) {
        throw std::invalid_argument(fmt::format("{}:{}: not an INI line (`key = value`, a [section], or a value "
                                                "continued on an indented line; lines up to 200 characters)",
                                                file.string(), rc));
    }
    return ini;
}

std::string trim(std::string s) {
    const auto not_space = [](unsigned char c) { return std::isspace(c) == 0; };
    s.erase(s.begin(), std::find_if(s.begin(), s.end(), not_space));
    s.erase(std::find_if(s.rbegin(), s.rend(), not_space).base(), s.end());
    return s;
}

/// Comma- or newline-separated list items.
std::vector<std::string> list_items(const std::string& value) {
    std::vector<std::string> items;
    std::string cur;
    for (const char c : value + ",") {
        if (c == ',' || c == '\n') {
            if (auto t = trim(cur); !t.empty()) items.push_back(std::move(t));
            cur.clear();
        } else {
            cur.push_back(c);
        }
    }
    return items;
}

class EnvLookup {
public:
    EnvLookup(const Ini& ini, std::string env) : ini_(ini), env_(std::move(env)) {}

    /// The key in [env:NAME], its extends (recursively), then [env].
    [[nodiscard]] std::optional<std::string> get(const std::string& key) const {
        std::vector<std::string> seen;
        if (auto v = in_section("env:" + env_, key, seen, 0)) return interpolate(*v, 0);
        if (const auto* v = ini_.find("env", key)) return interpolate(*v, 0);
        return std::nullopt;
    }

    [[nodiscard]] std::string interpolate(const std::string& value, int depth) const {
        static const std::regex ref(R"(\$\{([^}.]+)\.([^}]+)\})");
        if (depth > 10) fail(fmt::format("'{}': ${{...}} references nest too deep (a cycle?)", value));
        std::string out;
        auto begin = value.cbegin();
        std::smatch m;
        while (std::regex_search(begin, value.cend(), m, ref)) {
            out.append(begin, m[0].first);
            const std::string section = m[1].str();
            const std::string key = m[2].str();
            if (section == "sysenv") {
                const char* e = std::getenv(key.c_str());
                out += e != nullptr ? e : "";
            } else if (section == "this" && key == "__env__") {
                out += env_;
            } else if (section == "this") {
                const auto v = get(key);
                if (!v) fail(fmt::format("${{this.{}}}: [env:{}] has no {}", key, env_, key));
                out += *v;
            } else if (const auto* v = ini_.find(section, key)) {
                out += interpolate(*v, depth + 1);
            } else {
                fail(fmt::format("${{{}.{}}}: there is no {} in [{}]", section, key, key, section));
            }
            begin = m[0].second;
        }
        out.append(begin, value.cend());
        return out;
    }

    [[noreturn]] void fail(const std::string& what) const {
        throw std::invalid_argument(fmt::format("{}: [env:{}]: {}", ini_.file.string(), env_, what));
    }

private:
    std::optional<std::string> in_section(const std::string& section, const std::string& key,
                                          std::vector<std::string>& seen, int depth) const {
        if (std::find(seen.begin(), seen.end(), section) != seen.end() || depth > 10) {
            fail(fmt::format("extends: [{}] extends itself", section));
        }
        seen.push_back(section);
        if (const auto* v = ini_.find(section, key)) return *v;
        if (const auto* ext = ini_.find(section, "extends")) {
            for (const auto& parent : list_items(*ext)) {
                if (ini_.sections.find(parent) == ini_.sections.end()) {
                    fail(fmt::format("extends: there is no section [{}]", parent));
                }
                if (auto v = in_section(parent, key, seen, depth + 1)) return v;
            }
        }
        return std::nullopt;
    }

    const Ini& ini_;
    std::string env_;
};

std::string env_list(const Ini& ini) {
    std::string s;
    for (const auto& name : ini.order) {
        if (name.rfind("env:", 0) == 0) s += (s.empty() ? "" : ", ") + name.substr(4);
    }
    return s.empty() ? "none" : s;
}

/// The newest regular file under the folders (dot-names skipped).
std::optional<std::pair<fs::path, fs::file_time_type>> newest_file(const std::vector<fs::path>& roots) {
    std::optional<std::pair<fs::path, fs::file_time_type>> newest;
    const auto consider = [&](const fs::path& p) {
        const auto t = fs::last_write_time(p);
        if (!newest || t > newest->second) newest = {p, t};
    };
    for (const auto& root : roots) {
        if (fs::is_regular_file(root)) consider(root);
        if (!fs::is_directory(root)) continue;
        for (const auto& f : visible_files(root)) consider(root / f);
    }
    return newest;
}

}  // namespace

std::optional<hil::BoardModel> platformio_board(const std::string& board_id) {
    // PlatformIO's platform-atmelavr boards/*.json for the boards of
    // hil/board_description.cpp (same MCU, clock and Arduino variant).
    static const std::map<std::string, hil::BoardModel> ids = {
        {"uno", hil::BoardModel::uno},
        {"nanoatmega328", hil::BoardModel::nano},
        {"nanoatmega328new", hil::BoardModel::nano},
        {"pro8MHzatmega328", hil::BoardModel::pro_mini_8mhz},
        {"megaatmega2560", hil::BoardModel::mega2560},
    };
    const auto it = ids.find(board_id);
    return it == ids.end() ? std::nullopt : std::optional(it->second);
}

PlatformioProject load_platformio_project(const fs::path& dir, const std::string& env_name) {
    const fs::path ini_file = dir / "platformio.ini";
    if (!fs::is_regular_file(ini_file)) {
        throw std::invalid_argument(fmt::format("{}: no platformio.ini (not a PlatformIO project folder)", dir.string()));
    }
    const Ini ini = read_ini(ini_file);
    PlatformioProject p;
    p.dir = dir;
    p.env = env_name;
    if (p.env.empty()) {
        if (const auto* d = ini.find("platformio", "default_envs"); d != nullptr && !list_items(*d).empty()) {
            p.env = list_items(*d).front();
        } else {
            std::vector<std::string> envs;
            for (const auto& name : ini.order) {
                if (name.rfind("env:", 0) == 0) envs.push_back(name.substr(4));
            }
            if (envs.size() != 1) {
                throw std::invalid_argument(fmt::format("{}: give the environment (--env NAME or env: NAME): "
                                                        "no default_envs, and the environments are {}",
                                                        ini_file.string(), env_list(ini)));
            }
            p.env = envs.front();
        }
    }
    if (ini.sections.find("env:" + p.env) == ini.sections.end()) {
        throw std::invalid_argument(fmt::format("{}: no [env:{}] (the environments: {})", ini_file.string(), p.env,
                                                env_list(ini)));
    }
    const EnvLookup env(ini, p.env);
    const auto board_id = env.get("board");
    if (!board_id) env.fail("no board = ... (here, in its extends or in [env])");
    p.board_id = trim(*board_id);
    const auto model = platformio_board(p.board_id);
    if (!model) {
        env.fail(fmt::format("board = {}: ddmr-hil models uno, nanoatmega328, nanoatmega328new, pro8MHzatmega328 "
                             "and megaatmega2560 (docs/boards.md)",
                             p.board_id));
    }
    p.board = *model;
    const hil::BoardDescription& board = hil::board_description(p.board);
    if (const auto f_cpu = env.get("board_build.f_cpu")) {
        // "16000000L": digits, then an optional integer suffix.
        static const std::regex hz(R"(^\s*([0-9]+)[uUlL]*\s*$)");
        std::smatch m;
        if (!std::regex_match(*f_cpu, m, hz)) env.fail(fmt::format("board_build.f_cpu = {}: not a frequency in Hz", *f_cpu));
        if (std::stoull(m[1].str()) != board.clock_hz) {
            env.fail(fmt::format("board_build.f_cpu = {}: the {} runs at {} Hz in ddmr-hil", trim(*f_cpu), board.label,
                                 board.clock_hz));
        }
    }
    if (const auto mcu = env.get("board_build.mcu"); mcu && trim(*mcu) != board.mcu->name) {
        env.fail(fmt::format("board_build.mcu = {}: the {} has the {}", trim(*mcu), board.label, board.mcu->name));
    }
    // Folders, as [platformio] sets them (relative to the project).
    // `fallback` is already a path in the project.
    const auto folder = [&](const char* key, const fs::path& fallback) {
        const auto* v = ini.find("platformio", key);
        if (v == nullptr) return fallback;
        const fs::path path(env.interpolate(trim(*v), 0));
        return path.is_absolute() ? path : dir / path;
    };
    const fs::path workspace = folder("workspace_dir", dir / ".pio");
    const fs::path build_dir = folder("build_dir", workspace / "build");
    p.elf = build_dir / p.env / "firmware.elf";
    p.source_dirs = {ini_file, folder("src_dir", dir / "src"), folder("include_dir", dir / "include"),
                     folder("lib_dir", dir / "lib")};
    if (!fs::is_regular_file(p.elf)) {
        throw std::invalid_argument(fmt::format("{}: no ELF for [env:{}]: build it first with `pio run -e {}` "
                                                "(in {})",
                                                p.elf.string(), p.env, p.env, dir.string()));
    }
    if (const auto newest = newest_file(p.source_dirs); newest && newest->second > fs::last_write_time(p.elf)) {
        throw std::invalid_argument(fmt::format("{}: older than {}: build it again with `pio run -e {}`",
                                                p.elf.string(), newest->first.string(), p.env));
    }
    // The ELF must be a program for the board the environment names.
    try {
        hil::ElfImage::read(p.elf).require_mcu(*board.mcu, board.key);
    } catch (const std::exception&) {
        throw std::invalid_argument(fmt::format("{}: not a program for the {} of [env:{}] (board = {}): build it "
                                                "again with `pio run -e {}`, or correct board =",
                                                p.elf.string(), board.mcu->label, p.env, p.board_id, p.env));
    }
    return p;
}

nlohmann::json platformio_json(const PlatformioProject& project) {
    return {{"platformio", project.dir.string()},
            {"env", project.env},
            {"board_id", project.board_id},
            {"board", hil::board_description(project.board).key},
            {"elf", project.elf.string()}};
}

}  // namespace ddmr::tools
