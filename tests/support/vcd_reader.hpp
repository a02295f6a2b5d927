#pragma once
// A small VCD reader for tests: the declared signals (by full name
// scope.name) and every value change in file order, with a check that the
// file has the structure GTKWave needs ($timescale, balanced scopes,
// $enddefinitions, timestamps before changes). Independent of VcdWriter's
// code, so the tests check the file rather than the writer's own view.
#include <cstdint>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace ddmr::test {

struct VcdChange {
    uint64_t time = 0;  ///< in the file's timescale units
    uint64_t value = 0;
};

struct VcdVar {
    std::string full_name;  ///< "top.scope.name"
    unsigned width = 1;
    std::vector<VcdChange> changes;  ///< $dumpvars value first, then each change
};

struct VcdFile {
    std::string timescale;             ///< e.g. "1ns"
    std::vector<std::string> comments;
    std::map<std::string, VcdVar> vars;  ///< by full name
    std::vector<uint64_t> timestamps;    ///< every #t in file order
    bool has_dumpvars = false;
    uint64_t end_time = 0;               ///< last timestamp

    const VcdVar& var(const std::string& full_name) const {
        const auto it = vars.find(full_name);
        if (it == vars.end()) throw std::runtime_error("VCD has no signal " + full_name);
        return it->second;
    }
    bool has(const std::string& full_name) const { return vars.count(full_name) != 0; }
};

/// Parses `text`; throws std::runtime_error on a structural error.
inline VcdFile parse_vcd(const std::string& text) {
    VcdFile f;
    std::istringstream in(text);
    std::string tok;
    std::vector<std::string> scopes;
    std::map<std::string, std::string> id_to_name;
    bool definitions_done = false;
    bool have_time = false;
    uint64_t now = 0;
    const auto read_until_end = [&in]() {
        std::vector<std::string> words;
        std::string w;
        while (in >> w && w != "$end") words.push_back(w);
        if (w != "$end") throw std::runtime_error("VCD: missing $end");
        return words;
    };
    const auto apply = [&](const std::string& id, uint64_t value) {
        const auto it = id_to_name.find(id);
        if (it == id_to_name.end()) throw std::runtime_error("VCD: change of undeclared id " + id);
        if (!have_time) throw std::runtime_error("VCD: change before the first timestamp");
        f.vars[it->second].changes.push_back(VcdChange{now, value});
    };
    while (in >> tok) {
        if (!definitions_done) {
            if (tok == "$timescale") {
                const auto w = read_until_end();
                for (const auto& s : w) f.timescale += s;
            } else if (tok == "$comment") {
                const auto w = read_until_end();
                std::string line;
                for (const auto& s : w) line += (line.empty() ? "" : " ") + s;
                f.comments.push_back(line);
            } else if (tok == "$scope") {
                const auto w = read_until_end();
                if (w.size() != 2) throw std::runtime_error("VCD: bad $scope");
                scopes.push_back(w[1]);
            } else if (tok == "$upscope") {
                read_until_end();
                if (scopes.empty()) throw std::runtime_error("VCD: $upscope without $scope");
                scopes.pop_back();
            } else if (tok == "$var") {
                const auto w = read_until_end();
                if (w.size() < 4) throw std::runtime_error("VCD: bad $var");
                std::string full;
                for (const auto& s : scopes) full += s + ".";
                full += w[3];
                VcdVar v;
                v.full_name = full;
                v.width = static_cast<unsigned>(std::stoul(w[1]));
                if (f.vars.count(full) != 0) throw std::runtime_error("VCD: duplicate " + full);
                id_to_name[w[2]] = full;
                f.vars[full] = v;
            } else if (tok == "$enddefinitions") {
                read_until_end();
                if (!scopes.empty()) throw std::runtime_error("VCD: unbalanced $scope");
                definitions_done = true;
            } else if (tok == "$date" || tok == "$version") {
                read_until_end();
            } else {
                throw std::runtime_error("VCD: unexpected '" + tok + "' in the header");
            }
            continue;
        }
        if (tok == "$dumpvars") {
            f.has_dumpvars = true;
        } else if (tok == "$end" || tok == "$dumpall" || tok == "$dumpon" || tok == "$dumpoff") {
        } else if (tok[0] == '#') {
            const uint64_t t = std::stoull(tok.substr(1));
            if (have_time && t < now) throw std::runtime_error("VCD: time goes back at #" + std::to_string(t));
            now = t;
            have_time = true;
            f.timestamps.push_back(t);
            f.end_time = t;
        } else if (tok[0] == 'b' || tok[0] == 'B') {
            std::string id;
            in >> id;
            apply(id, std::stoull(tok.substr(1), nullptr, 2));
        } else if (tok[0] == '0' || tok[0] == '1') {
            apply(tok.substr(1), tok[0] == '1' ? 1 : 0);
        } else {
            throw std::runtime_error("VCD: unexpected '" + tok + "'");
        }
    }
    if (!definitions_done) throw std::runtime_error("VCD: no $enddefinitions");
    return f;
}

/// Level transitions of a 1-bit signal after its initial value.
inline std::size_t edge_count(const VcdVar& v, bool rising_only = false) {
    std::size_t n = 0;
    for (std::size_t i = 1; i < v.changes.size(); ++i) {
        if (v.changes[i].value == v.changes[i - 1].value) continue;
        if (!rising_only || v.changes[i].value != 0) ++n;
    }
    return n;
}

}  // namespace ddmr::test
