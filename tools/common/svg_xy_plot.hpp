#pragma once
// A small X-Y track plot as SVG text (calibrate's before/after plots): the
// robot's paths in the plane, equal scale on both axes, a grid at round
// metres, a legend. Self-contained (no fonts or scripts fetched), viewable in
// any browser or Markdown viewer, and byte-identical for the same input
// (numbers printed with fixed precision).
#include <string>
#include <utility>
#include <vector>

namespace ddmr::tools {

struct XySeries {
    std::string name;    ///< in the legend
    std::string colour;  ///< an SVG colour ("#1f77b4")
    bool dashed = false;
    bool markers = false;  ///< a dot per point instead of a line (logged samples)
    std::vector<std::pair<double, double>> points;  ///< [m]
};

/// The plot, `title` above it; axes labelled x [m] and y [m]. Throws
/// std::invalid_argument for no point at all or a non-finite one.
std::string svg_xy_plot(const std::string& title, const std::vector<XySeries>& series);

}  // namespace ddmr::tools
