#include "common/csv_table.hpp"

#include <fmt/format.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace ddmr::tools {

namespace fs = std::filesystem;

const std::vector<double>& Table::col(const std::string& name, const fs::path& file) const {
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (names[i] == name) return columns[i];
    }
    throw std::runtime_error(file.string() + ": no column '" + name + "'");
}

Table read_table(const fs::path& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error(path.string() + ": cannot read");
    Table t;
    std::string line;
    if (!std::getline(in, line)) throw std::runtime_error(path.string() + ": empty file");
    std::stringstream header(line);
    for (std::string name; std::getline(header, name, ',');) t.names.push_back(name);
    t.columns.resize(t.names.size());
    std::size_t row = 1;
    while (std::getline(in, line)) {
        ++row;
        std::stringstream ss(line);
        std::size_t c = 0;
        for (std::string cell; std::getline(ss, cell, ','); ++c) {
            if (c >= t.names.size()) throw std::runtime_error(fmt::format("{}:{}: too many columns", path.string(), row));
            char* end = nullptr;
            const double v = std::strtod(cell.c_str(), &end);
            if (end == cell.c_str() || *end != '\0') {
                throw std::runtime_error(fmt::format("{}:{}: '{}' in column {} is not a number", path.string(), row,
                                                     cell, t.names[c]));
            }
            t.columns[c].push_back(v);
        }
        if (c != t.names.size()) throw std::runtime_error(fmt::format("{}:{}: {} columns, expected {}",
                                                                      path.string(), row, c, t.names.size()));
    }
    return t;
}

}  // namespace ddmr::tools
