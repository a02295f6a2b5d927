#pragma once
// A part's truth.csv value by column ("NAME.COLUMN"), for the parts tests.

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "hil/parts/part_set.hpp"

namespace ddmr::test {

/// The value of truth column `column` now; a test failure (and -1) when the
/// parts have no such column.
inline double truth_value(const hil::PartSet& parts, const std::string& column) {
    std::vector<double> values;
    parts.truth_values(values);
    const auto columns = parts.truth_columns();
    for (std::size_t i = 0; i < columns.size(); ++i) {
        if (columns[i] == column) return values[i];
    }
    ADD_FAILURE() << "no truth column " << column;
    return -1;
}

}  // namespace ddmr::test
