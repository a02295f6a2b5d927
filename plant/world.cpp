#include "plant/world.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "plant/segment_clip.hpp"
#include "plant/units.hpp"

namespace ddmr::plant {
namespace {

Eigen::Vector2d unit(double angle_rad) { return {std::cos(angle_rad), std::sin(angle_rad)}; }

/// The z of the cross product of two plane vectors (> 0: b lies counter-clockwise of a).
double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

/// `angle` brought into [0, 2 pi).
double wrap_positive(double angle) {
    const double w = std::fmod(angle, 2.0 * kPi);
    return w < 0.0 ? w + 2.0 * kPi : w;
}

Eigen::Vector2d closest_on_segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
    const Eigen::Vector2d ab = b - a;
    const double len2 = ab.squaredNorm();
    if (len2 == 0.0) return a;
    return a + std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) * ab;
}

Eigen::Vector2d closest_on_arc(const LinePiece& arc, const Eigen::Vector2d& p) {
    const Eigen::Vector2d v = p - arc.center_m;
    if (v.squaredNorm() == 0.0) return arc.start_point();  // every point is as near
    const double phi = std::atan2(v.y(), v.x());
    const double along = arc.sweep_rad >= 0.0 ? wrap_positive(phi - arc.start_rad) : wrap_positive(arc.start_rad - phi);
    if (along <= std::fabs(arc.sweep_rad)) return arc.center_m + arc.radius_m * unit(phi);
    const Eigen::Vector2d s = arc.start_point();
    const Eigen::Vector2d e = arc.end_point();
    return (p - s).squaredNorm() <= (p - e).squaredNorm() ? s : e;
}

/// Rounding in a distance of points within metres of the origin is far
/// below this [m].
constexpr double kRoundingMargin_m = 1e-9;

/// True if `p` lies within `half_m` of the piece's centreline. An arc lies
/// on its circle, so a point farther than half_m from the circle (by more
/// than rounding) is farther from the arc: that test needs no angle, and
/// rejects most pieces of a course; the rest are measured exactly.
bool within(const LinePiece& piece, const Eigen::Vector2d& p, double half_m) {
    if (piece.kind == LinePiece::Kind::arc &&
        std::fabs((p - piece.center_m).norm() - piece.radius_m) > half_m + kRoundingMargin_m) {
        return false;
    }
    return (p - closest_point(piece, p)).norm() <= half_m;
}

/// Wall `w`'s nearest point inside the cone's angle, or none.
std::optional<ConeHit> hit_in_cone(const Wall& w, const Cone& cone) {
    const Eigen::Vector2d w0 = w.a_m - cone.origin_m;
    const Eigen::Vector2d dw = w.b_m - w.a_m;
    const Eigen::Vector2d right = unit(cone.direction_rad - cone.half_angle_rad);
    const Eigen::Vector2d left = unit(cone.direction_rad + cone.half_angle_rad);
    double lo = 0.0, hi = 1.0;
    // Counter-clockwise of the right edge, clockwise of the left edge.
    if (!clip_to_half_plane(cross(right, w0), cross(right, dw), lo, hi)) return std::nullopt;
    if (!clip_to_half_plane(-cross(left, w0), -cross(left, dw), lo, hi)) return std::nullopt;
    const double len2 = dw.squaredNorm();
    const double t = len2 == 0.0 ? lo : std::clamp(-w0.dot(dw) / len2, lo, hi);
    const Eigen::Vector2d ray = w0 + t * dw;
    ConeHit h;
    h.distance_m = ray.norm();
    h.point_m = cone.origin_m + ray;
    if (h.distance_m > 0.0 && len2 > 0.0) {
        const Eigen::Vector2d normal = Eigen::Vector2d(-dw.y(), dw.x()) / std::sqrt(len2);
        h.incidence_rad = std::acos(std::min(1.0, std::fabs(normal.dot(ray / h.distance_m))));
    }
    return h;
}

}  // namespace

LinePiece LinePiece::segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    LinePiece p;
    p.kind = Kind::segment;
    p.a_m = a;
    p.b_m = b;
    return p;
}

LinePiece LinePiece::arc(const Eigen::Vector2d& center, double radius_m, double start_rad, double sweep_rad) {
    LinePiece p;
    p.kind = Kind::arc;
    p.center_m = center;
    p.radius_m = radius_m;
    p.start_rad = start_rad;
    p.sweep_rad = sweep_rad;
    return p;
}

Eigen::Vector2d LinePiece::start_point() const {
    return kind == Kind::segment ? a_m : Eigen::Vector2d(center_m + radius_m * unit(start_rad));
}

Eigen::Vector2d LinePiece::end_point() const {
    return kind == Kind::segment ? b_m : Eigen::Vector2d(center_m + radius_m * unit(start_rad + sweep_rad));
}

double LinePiece::end_heading_rad() const {
    if (kind == Kind::segment) return std::atan2(b_m.y() - a_m.y(), b_m.x() - a_m.x());
    return start_rad + sweep_rad + (sweep_rad >= 0.0 ? kPi / 2.0 : -kPi / 2.0);
}

double LinePiece::length_m() const {
    return kind == Kind::segment ? (b_m - a_m).norm() : radius_m * std::fabs(sweep_rad);
}

Eigen::Vector2d closest_point(const LinePiece& piece, const Eigen::Vector2d& p) {
    return piece.kind == LinePiece::Kind::segment ? closest_on_segment(piece.a_m, piece.b_m, p) : closest_on_arc(piece, p);
}

double reflectance_at(const World& world, const Eigen::Vector2d& p) {
    for (auto line = world.lines.rbegin(); line != world.lines.rend(); ++line) {
        const double half = line->width_m / 2.0;
        for (const LinePiece& piece : line->pieces) {
            if (within(piece, p, half)) return line->reflectance;
        }
    }
    return world.floor_reflectance;
}

bool clear_of_lines(const World& world, const Eigen::Vector2d& p, double radius_m) {
    for (const FloorLine& line : world.lines) {
        // Every point within radius_m of p is farther than half the width
        // from each piece's centreline (an arc: from its whole circle first).
        const double reach = line.width_m / 2.0 + radius_m + kRoundingMargin_m;
        for (const LinePiece& piece : line.pieces) {
            if (piece.kind == LinePiece::Kind::arc && std::fabs((p - piece.center_m).norm() - piece.radius_m) > reach) {
                continue;
            }
            if ((p - closest_point(piece, p)).norm() <= reach) return false;
        }
    }
    return true;
}

std::optional<LineOffset> line_offset(const World& world, const Eigen::Vector2d& p, double heading_rad) {
    std::optional<LineOffset> best;
    const Eigen::Vector2d left(-std::sin(heading_rad), std::cos(heading_rad));
    for (std::size_t i = 0; i < world.lines.size(); ++i) {
        for (const LinePiece& piece : world.lines[i].pieces) {
            const Eigen::Vector2d c = closest_point(piece, p);
            const double d = (c - p).norm();
            if (best && d >= best->distance_m) continue;
            best = LineOffset{i, (c - p).dot(left), d};
        }
    }
    return best;
}

std::optional<ConeHit> cast_cone(const World& world, const Cone& cone) {
    std::optional<ConeHit> best;
    for (std::size_t i = 0; i < world.walls.size(); ++i) {
        const Wall& w = world.walls[i];
        if (w.height_m < cone.height_m) continue;
        // No point of a wall is nearer than its nearest point: one beyond the
        // range (or beyond the best hit so far) cannot be hit.
        const double nearest_sq = (closest_on_segment(w.a_m, w.b_m, cone.origin_m) - cone.origin_m).squaredNorm();
        const double reach = best ? std::min(best->distance_m, cone.max_range_m) : cone.max_range_m;
        if (nearest_sq > reach * reach) continue;
        std::optional<ConeHit> h = hit_in_cone(w, cone);
        if (!h || h->distance_m > cone.max_range_m || h->incidence_rad > cone.max_incidence_rad) continue;
        if (best && h->distance_m >= best->distance_m) continue;
        h->wall = i;
        best = h;
    }
    return best;
}

double nearest_wall_distance(const World& world, const Eigen::Vector2d& p) {
    double best = std::numeric_limits<double>::infinity();
    for (const Wall& w : world.walls) best = std::min(best, (p - closest_on_segment(w.a_m, w.b_m, p)).norm());
    return best;
}

std::optional<std::size_t> find_obstacle(const World& world, const std::string& name) {
    for (std::size_t i = 0; i < world.obstacles.size(); ++i) {
        if (world.obstacles[i] == name) return i;
    }
    return std::nullopt;
}

void move_obstacle(World& world, std::size_t index, const Eigen::Vector2d& delta_m) {
    for (Wall& w : world.walls) {
        if (w.obstacle != static_cast<int>(index)) continue;
        w.a_m += delta_m;
        w.b_m += delta_m;
    }
}

}  // namespace ddmr::plant
