#pragma once
// The plant's ground-truth CSV, shared by `ddmr-hil plant` (plant.csv) and
// `ddmr-hil run` (truth.csv, which adds the drive the plant received).
#include <string>
#include <vector>

#include "hil/plant_coupler.hpp"

namespace ddmr::tools {

/// "t_s,x_m,...,edges1,edges2[,duty1,duty2,dir1,dir2]\n"
std::string truth_csv_header(bool with_drive);

/// Appends one row for `s`.
void append_truth_row(std::string& out, const hil::TruthSample& s, bool with_drive);

/// Appends the row's values as numbers, in the header's order (the Python
/// API's truth history).
void append_truth_values(std::vector<double>& out, const hil::TruthSample& s, bool with_drive);

}  // namespace ddmr::tools
