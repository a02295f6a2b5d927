#include "common/svg_xy_plot.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace ddmr::tools {
namespace {

constexpr double kPlotPx = 480.0;   ///< the longer axis, in pixels
constexpr double kMarginPx = 56.0;  ///< room for tick labels
constexpr double kLegendPx = 18.0;  ///< per legend row

/// A tick step of 1, 2 or 5 x 10^k giving 4 to 10 ticks over `span`.
double tick_step(double span) {
    const double raw = span / 6.0;
    const double p = std::pow(10.0, std::floor(std::log10(raw)));
    for (const double m : {1.0, 2.0, 5.0, 10.0}) {
        if (m * p >= raw) return m * p;
    }
    return 10.0 * p;
}

std::string escape(const std::string& s) {
    std::string out;
    for (const char c : s) {
        switch (c) {
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '&': out += "&amp;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

}  // namespace

std::string svg_xy_plot(const std::string& title, const std::vector<XySeries>& series) {
    struct Span {
        double lo = std::numeric_limits<double>::infinity();
        double hi = -std::numeric_limits<double>::infinity();
        void add(double v) {
            lo = std::min(lo, v);
            hi = std::max(hi, v);
        }
    };
    Span xs;
    Span ys;
    for (const XySeries& s : series) {
        for (const auto& [x, y] : s.points) {
            if (!std::isfinite(x) || !std::isfinite(y)) throw std::invalid_argument("xy plot: a point is not finite in " + s.name);
            xs.add(x);
            ys.add(y);
        }
    }
    double x0 = xs.lo;
    double x1 = xs.hi;
    double y0 = ys.lo;
    double y1 = ys.hi;
    if (!(x0 <= x1)) throw std::invalid_argument("xy plot: nothing to plot");
    // Equal scale: the longer span sets the pixels per metre.
    const double pad = 0.05 * std::max({x1 - x0, y1 - y0, 0.01});
    x0 -= pad;
    x1 += pad;
    y0 -= pad;
    y1 += pad;
    const double scale = kPlotPx / std::max(x1 - x0, y1 - y0);
    const double w = (x1 - x0) * scale;
    const double h = (y1 - y0) * scale;
    const double legend_h = kLegendPx * static_cast<double>(series.size());
    const double width = w + 2.0 * kMarginPx;
    const double height = h + 2.0 * kMarginPx + legend_h;
    const auto px = [&](double x) { return kMarginPx + (x - x0) * scale; };
    const auto py = [&](double y) { return kMarginPx + (y1 - y) * scale; };

    std::string o = fmt::format(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" viewBox=\"0 0 {:.0f} {:.0f}\" "
        "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        width, height, width, height);
    o += fmt::format("<text x=\"{:.1f}\" y=\"24\" text-anchor=\"middle\" font-size=\"14\">{}</text>\n", width / 2.0,
                     escape(title));
    const double step = tick_step(std::max(x1 - x0, y1 - y0));
    for (double t = std::ceil(x0 / step) * step; t <= x1; t += step) {
        o += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{0:.1f}\" y2=\"{2:.1f}\" stroke=\"#ddd\"/>"
                         "<text x=\"{0:.1f}\" y=\"{3:.1f}\" text-anchor=\"middle\">{4:g}</text>\n",
                         px(t), py(y1), py(y0), py(y0) + 16.0, std::round(t / step) * step);
    }
    for (double t = std::ceil(y0 / step) * step; t <= y1; t += step) {
        o += fmt::format("<line x1=\"{0:.1f}\" y1=\"{1:.1f}\" x2=\"{2:.1f}\" y2=\"{1:.1f}\" stroke=\"#ddd\"/>"
                         "<text x=\"{3:.1f}\" y=\"{4:.1f}\" text-anchor=\"end\">{5:g}</text>\n",
                         px(x0), py(t), px(x1), px(x0) - 4.0, py(t) + 4.0, std::round(t / step) * step);
    }
    o += fmt::format("<rect x=\"{:.1f}\" y=\"{:.1f}\" width=\"{:.1f}\" height=\"{:.1f}\" fill=\"none\" stroke=\"black\"/>\n",
                     px(x0), py(y1), w, h);
    o += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\" text-anchor=\"middle\">x [m]</text>\n", px(x0) + w / 2.0,
                     py(y0) + 34.0);
    o += fmt::format("<text transform=\"translate({:.1f},{:.1f}) rotate(-90)\" text-anchor=\"middle\">y [m]</text>\n",
                     px(x0) - 40.0, py(y1) + h / 2.0);
    for (std::size_t i = 0; i < series.size(); ++i) {
        const XySeries& s = series[i];
        if (s.markers) {
            o += fmt::format("<g fill=\"{}\">", s.colour);
            for (const auto& [x, y] : s.points) o += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"1.8\"/>", px(x), py(y));
            o += "</g>\n";
        } else {
            o += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\"{} points=\"", s.colour,
                             s.dashed ? " stroke-dasharray=\"6 4\"" : "");
            for (const auto& [x, y] : s.points) o += fmt::format("{:.1f},{:.1f} ", px(x), py(y));
            o += "\"/>\n";
        }
        const double ly = py(y0) + 52.0 + kLegendPx * static_cast<double>(i);
        if (s.markers) {
            o += fmt::format("<circle cx=\"{:.1f}\" cy=\"{:.1f}\" r=\"3\" fill=\"{}\"/>", px(x0) + 12.0, ly - 4.0, s.colour);
        } else {
            o += fmt::format("<line x1=\"{:.1f}\" y1=\"{:.1f}\" x2=\"{:.1f}\" y2=\"{:.1f}\" stroke=\"{}\" stroke-width=\"2\"{}/>",
                             px(x0), ly - 4.0, px(x0) + 24.0, ly - 4.0, s.colour, s.dashed ? " stroke-dasharray=\"6 4\"" : "");
        }
        o += fmt::format("<text x=\"{:.1f}\" y=\"{:.1f}\">{}</text>\n", px(x0) + 32.0, ly, escape(s.name));
    }
    o += "</svg>\n";
    return o;
}

}  // namespace ddmr::tools
