#include "common/world_json.hpp"

#include <algorithm>
#include <cmath>

#include "plant/units.hpp"

namespace ddmr::tools {
namespace {

using json = nlohmann::ordered_json;

/// A length to 0.1 mm, as text-stable JSON.
double mm01(double v) { return std::round(v * 1e4) / 1e4; }

json point(const Eigen::Vector2d& p) { return json::array({mm01(p.x()), mm01(p.y())}); }

/// The centreline of one line, its pieces end to end.
json centreline(const plant::FloorLine& line) {
    json pts = json::array();
    for (const plant::LinePiece& piece : line.pieces) {
        if (pts.empty()) pts.push_back(point(piece.start_point()));
        if (piece.kind == plant::LinePiece::Kind::segment) {
            pts.push_back(point(piece.end_point()));
            continue;
        }
        const int n = std::max(8, static_cast<int>(std::ceil(std::fabs(piece.sweep_rad) / (2.0 * plant::kPi / 180.0))));
        for (int k = 1; k <= n; ++k) {
            const double a = piece.start_rad + piece.sweep_rad * k / n;
            pts.push_back(point(piece.center_m + piece.radius_m * Eigen::Vector2d(std::cos(a), std::sin(a))));
        }
    }
    return pts;
}

}  // namespace

json world_json(const plant::World& world) {
    json out;
    out["floor_reflectance"] = world.floor_reflectance;
    json lines = json::array();
    for (const plant::FloorLine& l : world.lines) {
        lines.push_back({{"width_m", l.width_m}, {"reflectance", l.reflectance}, {"points_m", centreline(l)}});
    }
    out["lines"] = lines;
    json walls = json::array();
    for (const plant::Wall& w : world.walls) {
        json j = {{"from_m", point(w.a_m)}, {"to_m", point(w.b_m)}, {"height_m", w.height_m}};
        if (w.obstacle >= 0) j["obstacle"] = world.obstacles[static_cast<std::size_t>(w.obstacle)];
        walls.push_back(j);
    }
    out["walls"] = walls;
    if (world.start) {
        out["start"] = {{"x_m", world.start->x_m}, {"y_m", world.start->y_m}, {"theta_rad", world.start->theta_rad}};
    }
    return out;
}

}  // namespace ddmr::tools
