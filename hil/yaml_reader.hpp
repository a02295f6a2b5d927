#pragma once
// YamlReader: reads the HIL's small YAML data files (board files, sketch
// contracts) with refusals that name the place and the key, as
// "FILE:LINE: key 'K': what is wrong" (std::runtime_error).

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

namespace ddmr::hil {

struct YamlReader {
    std::string source;  ///< the file, as the messages name it

    /// The file's root node; throws naming the file for an unreadable file
    /// (`what`: "the board file", ...) or malformed YAML (with its line).
    static YAML::Node load(const std::filesystem::path& path, const char* what);

    int line(const YAML::Node& n) const { return n.Mark().is_null() ? 0 : n.Mark().line + 1; }
    [[noreturn]] void fail(const YAML::Node& n, const std::string& key, const std::string& what) const;
    const YAML::Node& mapping(const YAML::Node& n, const std::string& key) const;
    /// Refuses a key of mapping `n` outside `allowed` (key = the mapping's own key, "" at the root).
    void only_keys(const YAML::Node& n, const std::string& key, const std::vector<std::string>& allowed) const;
    bool boolean(const YAML::Node& n, const std::string& key) const;
    /// A scalar as text (non-empty unless `allow_empty`).
    std::string text(const YAML::Node& n, const std::string& key, bool allow_empty = false) const;
    /// A finite number in [lo, hi].
    double number(const YAML::Node& n, const std::string& key, double lo, double hi) const;
    /// An integer in [lo, hi].
    long integer(const YAML::Node& n, const std::string& key, long lo, long hi) const;
    /// A list of non-empty scalars.
    std::vector<std::string> text_list(const YAML::Node& n, const std::string& key) const;
};

/// "FILE:LINE", or FILE when the line is unknown (0).
std::string file_line(const std::string& source, int line);

}  // namespace ddmr::hil
