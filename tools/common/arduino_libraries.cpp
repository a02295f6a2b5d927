#include "common/arduino_libraries.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <regex>
#include <sstream>
#include <stdexcept>

namespace ddmr::tools {
namespace fs = std::filesystem;

std::optional<fs::path> sketchbook_libraries() {
    if (const char* user = std::getenv("ARDUINO_DIRECTORIES_USER"); user != nullptr && *user != '\0') {
        return fs::path(user) / "libraries";
    }
    if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
        return fs::path(home) / "Arduino" / "libraries";
    }
    return std::nullopt;
}

std::optional<std::string> library_itself(const fs::path& dir) {
    if (fs::is_regular_file(dir / "library.properties")) return std::string("it has library.properties");
    std::vector<std::string> sources;  // sorted: the same message whatever the folder's order
    for (const auto& e : fs::directory_iterator(dir)) {
        const std::string ext = e.path().extension().string();
        if (e.is_regular_file() && (ext == ".h" || ext == ".hpp" || ext == ".cpp" || ext == ".c")) {
            sources.push_back(e.path().filename().string());
        }
    }
    if (sources.empty()) return std::nullopt;
    return fmt::format("it has {} at its top", *std::min_element(sources.begin(), sources.end()));
}

LibraryFolders library_folders(const fs::path& ino, const std::vector<fs::path>& named) {
    LibraryFolders f;
    const auto add = [&f](const fs::path& dir) {
        const fs::path abs = fs::absolute(dir).lexically_normal();
        for (const auto& seen : f.searched) {
            if (seen == abs) return;  // named twice: once is enough
        }
        f.searched.push_back(abs);
        if (fs::is_directory(abs)) f.existing.push_back(abs);
    };
    add(fs::absolute(ino).parent_path() / "src");
    for (const auto& dir : named) {
        if (!fs::is_directory(dir)) {
            throw std::invalid_argument(fmt::format("--libraries {}: no such folder", dir.string()));
        }
        if (const auto what = library_itself(dir)) {
            throw std::invalid_argument(fmt::format(
                "--libraries {}: a library itself ({}), not a folder of libraries: give the folder that holds it ({})",
                dir.string(), *what, fs::absolute(dir).lexically_normal().parent_path().string()));
        }
        add(dir);
    }
    if (const auto book = sketchbook_libraries()) add(*book);
    return f;
}

std::vector<UsedLibrary> parse_used_libraries(const std::string& log) {
    // arduino-builder 1.3.25 (legacy/builder/phases/libraries_builder.go's
    // messages): "Using library Servo at version 1.1.8 in folder: /x/Servo "
    // and "Using library Foo in folder: /x/Foo (legacy)".
    static const std::regex versioned(R"(^Using library (.+) at version (\S+) in folder: (.+?)\s*$)");
    static const std::regex legacy(R"(^Using library (.+) in folder: (.+?)(?: \(legacy\))?\s*$)");
    std::vector<UsedLibrary> used;
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_match(line, m, versioned)) {
            used.push_back({m[1].str(), m[2].str(), fs::path(m[3].str())});
        } else if (std::regex_match(line, m, legacy)) {
            used.push_back({m[1].str(), "", fs::path(m[2].str())});
        }
    }
    return used;
}

std::optional<MissingHeader> find_missing_header(const std::string& log) {
    static const std::regex missing(R"(^(.+?):([0-9]+):(?:[0-9]+:)? fatal error: (.+?): No such file or directory\s*$)");
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_match(line, m, missing)) return MissingHeader{fs::path(m[1].str()), std::stoi(m[2].str()), m[3].str()};
    }
    return std::nullopt;
}

std::vector<std::string> builder_warnings(const std::string& log) {
    // arduino-builder 1.3.25: 'Multiple libraries were found for "Lib.h"',
    // then ' Used: DIR' and ' Not used: DIR' lines.
    static const std::regex multiple(R"(^Multiple libraries were found for \"(.+)\"\s*$)");
    static const std::regex used(R"(^\s+Used: (.+?)\s*$)");
    static const std::regex not_used(R"(^\s+Not used: (.+?)\s*$)");
    std::vector<std::string> out;
    std::istringstream in(log);
    std::string header;
    std::string used_dir;
    std::vector<std::string> unused;
    const auto flush = [&] {
        if (header.empty()) return;
        std::string w = fmt::format("'{}' is in {} libraries: used {}", header, unused.size() + 1, used_dir);
        for (const auto& u : unused) w += ", not used " + u;
        if (std::find(out.begin(), out.end(), w) == out.end()) out.push_back(std::move(w));
        header.clear();
        used_dir.clear();
        unused.clear();
    };
    for (std::string line; std::getline(in, line);) {
        std::smatch m;
        if (std::regex_match(line, m, multiple)) {
            flush();
            header = m[1].str();
        } else if (!header.empty() && std::regex_match(line, m, used)) {
            used_dir = m[1].str();
        } else if (!header.empty() && std::regex_match(line, m, not_used)) {
            unused.push_back(m[1].str());
        } else {
            flush();
            if (line.rfind("WARNING: library ", 0) == 0 && line.find("claims to run on") != std::string::npos &&
                std::find(out.begin(), out.end(), line) == out.end()) {
                out.push_back(line.substr(std::string("WARNING: ").size()));
            }
        }
    }
    flush();
    return out;
}

std::optional<std::string> first_build_error(const std::string& log) {
    static const std::regex compiler(R"(^.+?:[0-9]+:(?:[0-9]+:)? (?:fatal )?error: .+$)");
    static const std::regex linker(R"(^.+(?:undefined reference to|multiple definition of) .+$)");
    std::istringstream in(log);
    for (std::string line; std::getline(in, line);) {
        if (!line.empty() && line.back() == '\r') line.pop_back();
        if (std::regex_match(line, compiler) || std::regex_match(line, linker)) return line;
    }
    return std::nullopt;
}

}  // namespace ddmr::tools
