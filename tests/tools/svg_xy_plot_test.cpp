// The X-Y track plot: equal scale on both axes, every series drawn, the
// legend escaped, and refused input.
#include "common/svg_xy_plot.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <regex>
#include <stdexcept>
#include <string>

namespace ddmr::tools {
namespace {

/// The value of attribute `name` on the first element that has it.
double attribute(const std::string& svg, const std::string& name) {
    std::smatch m;
    EXPECT_TRUE(std::regex_search(svg, m, std::regex(" " + name + "=\"([0-9.]+)\""))) << name;
    return std::stod(m[1].str());
}

TEST(SvgXyPlot, EqualScaleAndEverySeries) {
    // 1 m by 0.5 m, padded 5 % of 1 m each side: 1.1 x 0.6 m; 480 px for 1.1 m,
    // so 261.8 px for 0.6 m, plus 2 x 56 px margins (and 2 legend rows of 18 px).
    const std::string svg = svg_xy_plot("a <b> & c", {{"logged", "#000", false, true, {{0, 0}, {1, 0.5}}},
                                                      {"fit", "#00f", true, false, {{0, 0}, {0.5, 0.25}, {1, 0.5}}}});
    EXPECT_EQ(svg.rfind("<svg xmlns=\"http://www.w3.org/2000/svg\"", 0), 0U);
    EXPECT_NEAR(attribute(svg, "width"), 480 + 112, 0.5);
    EXPECT_NEAR(attribute(svg, "height"), 480.0 * 0.6 / 1.1 + 112 + 36, 0.5);
    EXPECT_NE(svg.find("a &lt;b&gt; &amp; c"), std::string::npos);
    EXPECT_NE(svg.find("<circle cx="), std::string::npos);        // the markers
    EXPECT_NE(svg.find("stroke-dasharray=\"6 4\" points="), std::string::npos);  // the dashed line
    EXPECT_NE(svg.find(">x [m]</text>"), std::string::npos);
    EXPECT_EQ(svg_xy_plot("t", {{"s", "#000", false, false, {{0, 0}, {1, 1}}}}),
              svg_xy_plot("t", {{"s", "#000", false, false, {{0, 0}, {1, 1}}}}));
}

TEST(SvgXyPlot, NothingOrNotFiniteIsRefused) {
    EXPECT_THROW((void)svg_xy_plot("t", {}), std::invalid_argument);
    EXPECT_THROW((void)svg_xy_plot("t", {{"s", "#000", false, false, {{0, std::nan("")}}}}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::tools
