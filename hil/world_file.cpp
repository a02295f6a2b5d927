#include "hil/world_file.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "hil/yaml_reader.hpp"
#include "plant/units.hpp"

namespace ddmr::hil {
namespace {

using plant::LinePiece;

constexpr double kDeg = plant::kPi / 180.0;
constexpr double kFarM = 1e4;  ///< coordinates within 10 km: a typo, not a course, beyond

Eigen::Vector2d point(const YamlReader& r, const YAML::Node& n, const std::string& key) {
    if (!n.IsSequence() || n.size() != 2) r.fail(n, key, "expected a point [x, y] in metres");
    return {r.number(n[0], key, -kFarM, kFarM), r.number(n[1], key, -kFarM, kFarM)};
}

std::vector<Eigen::Vector2d> points(const YamlReader& r, const YAML::Node& n, const std::string& key,
                                    std::size_t at_least) {
    if (!n.IsSequence() || n.size() < at_least) {
        r.fail(n, key, fmt::format("expected a list of at least {} points [x, y]", at_least));
    }
    std::vector<Eigen::Vector2d> out;
    for (std::size_t i = 0; i < n.size(); ++i) out.push_back(point(r, n[i], fmt::format("{}[{}]", key, i)));
    return out;
}

/// A polyline's segments, refusing two equal corners in a row (a piece of no length).
void add_polyline(const YamlReader& r, const YAML::Node& n, const std::string& key, bool closed,
                  std::vector<LinePiece>& out) {
    std::vector<Eigen::Vector2d> p = points(r, n, key, 2);
    if (closed) p.push_back(p.front());
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
        if (p[i] == p[i + 1]) r.fail(n, key, fmt::format("corners {} and {} are the same point", i, (i + 1) % n.size()));
        out.push_back(LinePiece::segment(p[i], p[i + 1]));
    }
}

/// One `path:` step from (at, heading): `straight_m: L` or `arc: {radius_m, turn_deg}`.
void add_path_step(const YamlReader& r, const YAML::Node& step, const std::string& key, Eigen::Vector2d& at,
                   double& heading, std::vector<LinePiece>& out) {
    r.mapping(step, key);
    r.only_keys(step, key, {"straight_m", "arc"});
    if (step.size() != 1) r.fail(step, key, "expected one of straight_m or arc");
    if (step["straight_m"]) {
        const double len = r.number(step["straight_m"], key + ".straight_m", 1e-6, kFarM);
        const Eigen::Vector2d end = at + len * Eigen::Vector2d(std::cos(heading), std::sin(heading));
        out.push_back(LinePiece::segment(at, end));
        at = end;
        return;
    }
    const YAML::Node arc = step["arc"];
    r.mapping(arc, key + ".arc");
    r.only_keys(arc, key + ".arc", {"radius_m", "turn_deg"});
    if (!arc["radius_m"] || !arc["turn_deg"]) r.fail(arc, key + ".arc", "needs radius_m and turn_deg");
    const double radius = r.number(arc["radius_m"], key + ".arc.radius_m", 1e-6, kFarM);
    const double turn = r.number(arc["turn_deg"], key + ".arc.turn_deg", -360.0, 360.0) * kDeg;
    if (turn == 0.0) r.fail(arc["turn_deg"], key + ".arc.turn_deg", "a turn of 0 degrees draws nothing");
    // Left turns (positive) curve around a centre on the left of the heading.
    const double side = turn > 0.0 ? 1.0 : -1.0;
    const Eigen::Vector2d center = at + side * radius * Eigen::Vector2d(-std::sin(heading), std::cos(heading));
    const Eigen::Vector2d from = at - center;
    const LinePiece piece = LinePiece::arc(center, radius, std::atan2(from.y(), from.x()), turn);
    out.push_back(piece);
    at = piece.end_point();
    heading += turn;
}

plant::FloorLine read_line(const YamlReader& r, const YAML::Node& n, const std::string& key) {
    r.mapping(n, key);
    r.only_keys(n, key, {"width_m", "reflectance", "points_m", "closed", "from_m", "heading_deg", "path"});
    plant::FloorLine line;
    if (n["width_m"]) {
        line.width_m = r.number(n["width_m"], key + ".width_m", 0.0, 10.0);
        if (line.width_m <= 0.0) r.fail(n["width_m"], key + ".width_m", "a line needs a width above 0");
    }
    if (n["reflectance"]) line.reflectance = r.number(n["reflectance"], key + ".reflectance", 0.0, 1.0);
    const bool closed = n["closed"] && r.boolean(n["closed"], key + ".closed");
    if (n["points_m"] && n["path"]) r.fail(n, key, "give points_m or path, not both");
    if (n["points_m"]) {
        add_polyline(r, n["points_m"], key + ".points_m", closed, line.pieces);
        return line;
    }
    if (!n["path"]) r.fail(n, key, "a line needs points_m (corners) or path (from_m, heading_deg and steps)");
    if (!n["from_m"]) r.fail(n, key, "a path needs from_m, its start point");
    if (n["closed"]) r.fail(n["closed"], key + ".closed", "closed is for points_m; a path closes where its steps end");
    Eigen::Vector2d at = point(r, n["from_m"], key + ".from_m");
    double heading = n["heading_deg"] ? r.number(n["heading_deg"], key + ".heading_deg", -360.0, 360.0) * kDeg : 0.0;
    const YAML::Node path = n["path"];
    if (!path.IsSequence() || path.size() == 0) r.fail(path, key + ".path", "expected a list of steps");
    for (std::size_t i = 0; i < path.size(); ++i) {
        add_path_step(r, path[i], fmt::format("{}.path[{}]", key, i), at, heading, line.pieces);
    }
    return line;
}

/// A wall's `name`: a new obstacle's index (a name used once).
int add_obstacle(const YamlReader& r, const YAML::Node& n, const std::string& key, plant::World& world) {
    const std::string name = r.text(n, key);
    if (name.empty()) r.fail(n, key, "an obstacle's name must not be empty");
    if (plant::find_obstacle(world, name)) r.fail(n, key, fmt::format("a second obstacle called '{}'", name));
    world.obstacles.push_back(name);
    return static_cast<int>(world.obstacles.size() - 1);
}

void read_walls(const YamlReader& r, const YAML::Node& n, plant::World& world) {
    if (!n.IsSequence()) r.fail(n, "walls", "expected a list of walls");
    for (std::size_t i = 0; i < n.size(); ++i) {
        const std::string key = fmt::format("walls[{}]", i);
        const YAML::Node w = n[i];
        r.mapping(w, key);
        r.only_keys(w, key, {"from_m", "to_m", "polygon_m", "height_m", "name"});
        const int obstacle = w["name"] ? add_obstacle(r, w["name"], key + ".name", world) : -1;
        const double height = w["height_m"] ? r.number(w["height_m"], key + ".height_m", 1e-3, 100.0) : plant::Wall{}.height_m;
        std::vector<Eigen::Vector2d> corners;
        if (w["polygon_m"]) {
            if (w["from_m"] || w["to_m"]) r.fail(w, key, "give from_m and to_m, or polygon_m, not both");
            corners = points(r, w["polygon_m"], key + ".polygon_m", 3);
            corners.push_back(corners.front());
        } else {
            if (!w["from_m"] || !w["to_m"]) r.fail(w, key, "a wall needs from_m and to_m, or polygon_m");
            corners = {point(r, w["from_m"], key + ".from_m"), point(r, w["to_m"], key + ".to_m")};
        }
        for (std::size_t c = 0; c + 1 < corners.size(); ++c) {
            if (corners[c] == corners[c + 1]) r.fail(w, key, "a wall of zero length (two corners at the same point)");
            world.walls.push_back(plant::Wall{corners[c], corners[c + 1], height, obstacle});
        }
    }
}

plant::Pose read_start(const YamlReader& r, const YAML::Node& n) {
    r.mapping(n, "start");
    r.only_keys(n, "start", {"x_m", "y_m", "heading_deg"});
    plant::Pose p;
    if (n["x_m"]) p.x_m = r.number(n["x_m"], "start.x_m", -kFarM, kFarM);
    if (n["y_m"]) p.y_m = r.number(n["y_m"], "start.y_m", -kFarM, kFarM);
    if (n["heading_deg"]) p.theta_rad = r.number(n["heading_deg"], "start.heading_deg", -360.0, 360.0) * kDeg;
    return p;
}

}  // namespace

plant::World load_world_file(const std::filesystem::path& path) {
    const YAML::Node root = YamlReader::load(path, "the world file");
    const YamlReader r{path.string()};
    if (!root.IsMap()) r.fail(root, "world", "a world file is a mapping (floor, start, lines, walls)");
    r.only_keys(root, "", {"floor", "start", "lines", "walls"});
    plant::World w;
    if (root["floor"]) {
        const YAML::Node floor = root["floor"];
        r.mapping(floor, "floor");
        r.only_keys(floor, "floor", {"reflectance"});
        if (floor["reflectance"]) w.floor_reflectance = r.number(floor["reflectance"], "floor.reflectance", 0.0, 1.0);
    }
    if (root["start"]) w.start = read_start(r, root["start"]);
    if (root["lines"]) {
        const YAML::Node lines = root["lines"];
        if (!lines.IsSequence()) r.fail(lines, "lines", "expected a list of lines");
        for (std::size_t i = 0; i < lines.size(); ++i) w.lines.push_back(read_line(r, lines[i], fmt::format("lines[{}]", i)));
    }
    if (root["walls"]) read_walls(r, root["walls"], w);
    return w;
}

}  // namespace ddmr::hil
