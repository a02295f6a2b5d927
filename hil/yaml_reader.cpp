#include "hil/yaml_reader.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ddmr::hil {

std::string file_line(const std::string& source, int line) {
    return line > 0 ? fmt::format("{}:{}", source, line) : source;
}

YAML::Node YamlReader::load(const std::filesystem::path& path, const char* what) {
    const std::string source = path.string();
    try {
        return YAML::LoadFile(source);
    } catch (const YAML::BadFile&) {
        throw std::runtime_error(fmt::format("{}: cannot read {}", source, what));
    } catch (const YAML::ParserException& e) {
        throw std::runtime_error(fmt::format("{}:{}: malformed YAML: {}", source, e.mark.line + 1, e.msg));
    }
}

void YamlReader::fail(const YAML::Node& n, const std::string& key, const std::string& what) const {
    throw std::runtime_error(fmt::format("{}: key '{}': {}", file_line(source, line(n)), key, what));
}

const YAML::Node& YamlReader::mapping(const YAML::Node& n, const std::string& key) const {
    if (!n.IsMap()) fail(n, key, "expected a mapping");
    return n;
}

void YamlReader::only_keys(const YAML::Node& n, const std::string& key, const std::vector<std::string>& allowed) const {
    for (const auto& kv : n) {
        const std::string k = kv.first.Scalar();
        if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
            std::string list;
            for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
            fail(kv.first, key.empty() ? k : fmt::format("{}.{}", key, k), fmt::format("unknown key (expected {})", list));
        }
    }
}

bool YamlReader::boolean(const YAML::Node& n, const std::string& key) const {
    if (n.IsScalar()) {
        const std::string& s = n.Scalar();
        if (s == "true") return true;
        if (s == "false") return false;
    }
    fail(n, key, "expected true or false");
}

std::string YamlReader::text(const YAML::Node& n, const std::string& key, bool allow_empty) const {
    if (!n.IsScalar() || (!allow_empty && n.Scalar().empty())) fail(n, key, "expected a text");
    return n.Scalar();
}

double YamlReader::number(const YAML::Node& n, const std::string& key, double lo, double hi) const {
    double v = 0.0;
    if (!n.IsScalar()) fail(n, key, "expected a number");
    try {
        std::size_t used = 0;
        v = std::stod(n.Scalar(), &used);
        if (used != n.Scalar().size()) throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
        fail(n, key, fmt::format("'{}' is not a number", n.Scalar()));
    }
    if (!std::isfinite(v) || v < lo || v > hi) fail(n, key, fmt::format("{} is outside [{}, {}]", n.Scalar(), lo, hi));
    return v;
}

long YamlReader::integer(const YAML::Node& n, const std::string& key, long lo, long hi) const {
    long v = 0;
    if (!n.IsScalar()) fail(n, key, "expected an integer");
    try {
        std::size_t used = 0;
        v = std::stol(n.Scalar(), &used, 0);
        if (used != n.Scalar().size()) throw std::invalid_argument("trailing text");
    } catch (const std::exception&) {
        fail(n, key, fmt::format("'{}' is not an integer", n.Scalar()));
    }
    if (v < lo || v > hi) fail(n, key, fmt::format("{} is outside [{}, {}]", v, lo, hi));
    return v;
}

std::vector<std::string> YamlReader::text_list(const YAML::Node& n, const std::string& key) const {
    if (!n.IsSequence()) fail(n, key, "expected a list");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < n.size(); ++i) out.push_back(text(n[i], fmt::format("{}[{}]", key, i)));
    return out;
}

}  // namespace ddmr::hil
