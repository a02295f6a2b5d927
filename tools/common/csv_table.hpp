#pragma once
// A numeric CSV file with a header row, read into columns by name (the
// run's truth.csv, eeprom_log.csv, firmware.csv, ...). Every cell must be a
// number; errors name the file, the row and the column.

#include <filesystem>
#include <string>
#include <vector>

namespace ddmr::tools {

/// Columns of a CSV file with a header row, by name.
struct Table {
    std::vector<std::string> names;
    std::vector<std::vector<double>> columns;
    /// The column `name`; throws std::runtime_error naming `file` if absent.
    const std::vector<double>& col(const std::string& name, const std::filesystem::path& file) const;
    std::size_t rows() const { return columns.empty() ? 0 : columns[0].size(); }
};

/// Reads `path`; throws std::runtime_error naming the file (and row, column).
Table read_table(const std::filesystem::path& path);

}  // namespace ddmr::tools
