#pragma once
// World: what lies around the robot (docs/world.md): the floor and the tape
// lines on it, which reflectance sensors see, and the walls, which ultrasonic
// and IR sensors see and the chassis cannot pass. Plain data and pure
// geometry in the inertial frame of plant::Pose [m, rad]; no sensor model
// here: the sensor parts (hil/parts/) turn these reflectances and distances
// into pin levels, voltages and echo times with their datasheets.
//
// Lines are drawn as a centreline of pieces (straight segments and circular
// arcs, exact: an oval is two straights and two half circles) with a width:
// a point is on the line when it lies within width / 2 of the centreline
// (so a line's open ends are round).
// Where lines cross, the one listed last lies on top.
// Walls are vertical segments with a height; a box or an arena is the closed
// polygon of its edges.

#include <Eigen/Core>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "plant/diff_drive_kinematics.hpp"

namespace ddmr::plant {

/// Reflectance defaults: the fraction of the sensors' IR that a surface sends
/// back, 0 (none) .. 1. White paper and matt black vinyl tape, our estimates
/// (no datasheet gives a floor's IR reflectance; the sensors' own
/// calibration maps what they see).
inline constexpr double kWhiteReflectance = 0.8;
inline constexpr double kBlackTapeReflectance = 0.05;

/// One piece of a line's centreline: a segment from a_m to b_m, or an arc of
/// radius_m around center_m from angle start_rad through sweep_rad
/// (counter-clockwise positive; |sweep| <= 2 pi).
struct LinePiece {
    enum class Kind : unsigned char { segment, arc };
    Kind kind = Kind::segment;
    Eigen::Vector2d a_m = Eigen::Vector2d::Zero();
    Eigen::Vector2d b_m = Eigen::Vector2d::Zero();
    Eigen::Vector2d center_m = Eigen::Vector2d::Zero();
    double radius_m = 0.0;
    double start_rad = 0.0;
    double sweep_rad = 0.0;

    static LinePiece segment(const Eigen::Vector2d& a, const Eigen::Vector2d& b);
    static LinePiece arc(const Eigen::Vector2d& center, double radius_m, double start_rad, double sweep_rad);
    /// Where the piece starts and ends, and its direction of travel there [rad].
    [[nodiscard]] Eigen::Vector2d start_point() const;
    [[nodiscard]] Eigen::Vector2d end_point() const;
    [[nodiscard]] double end_heading_rad() const;
    [[nodiscard]] double length_m() const;
};

/// A tape line on the floor.
struct FloorLine {
    std::vector<LinePiece> pieces;
    double width_m = 0.019;  ///< 3/4" electrical tape, the common course line (SENSORS.md section 2)
    double reflectance = kBlackTapeReflectance;
};

/// A vertical wall from a_m to b_m.
struct Wall {
    Eigen::Vector2d a_m = Eigen::Vector2d::Zero();
    Eigen::Vector2d b_m = Eigen::Vector2d::Zero();
    double height_m = 0.2;
    int obstacle = -1;  ///< the named obstacle it belongs to (index in World::obstacles); -1: none
};

struct World {
    double floor_reflectance = kWhiteReflectance;
    std::vector<FloorLine> lines;
    std::vector<Wall> walls;
    std::vector<std::string> obstacles;  ///< the names of walls that a scenario may move (a box, a door)
    std::optional<Pose> start;  ///< the robot's pose at power-on; none: the origin, heading +x
};

/// The index of obstacle `name` in World::obstacles, if there is one.
std::optional<std::size_t> find_obstacle(const World& world, const std::string& name);
/// Moves every wall of obstacle `index` by `delta_m`.
void move_obstacle(World& world, std::size_t index, const Eigen::Vector2d& delta_m);

/// The point of a piece's centreline nearest to `p`.
Eigen::Vector2d closest_point(const LinePiece& piece, const Eigen::Vector2d& p);

/// What the floor sends back at `p`: the top line covering it, else the floor.
double reflectance_at(const World& world, const Eigen::Vector2d& p);
/// True if no line covers any point within `radius_m` of `p` (by more than
/// rounding): reflectance_at reads the floor everywhere there. One distance
/// per piece, where a spot's 13 reads would take 13.
bool clear_of_lines(const World& world, const Eigen::Vector2d& p, double radius_m);

/// The nearest line's centreline as seen from a point of the robot.
struct LineOffset {
    std::size_t line = 0;  ///< index in World::lines
    /// The centreline's offset across the robot's heading [m]: positive when
    /// the line lies to the left of the point.
    double lateral_m = 0.0;
    double distance_m = 0.0;  ///< to the nearest centreline point
};
/// The line nearest to `p` and its lateral offset for a robot heading
/// `heading_rad`; none when the world has no lines.
std::optional<LineOffset> line_offset(const World& world, const Eigen::Vector2d& p, double heading_rad);

/// A beam (a sonar's or an IR module's cone) cast from a point.
struct Cone {
    Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
    double direction_rad = 0.0;
    double half_angle_rad = 0.0;    ///< half the full angle, in [0, pi/2)
    double max_incidence_rad = 0.0; ///< a wall struck more obliquely sends the sound away: no echo
    double max_range_m = 0.0;
    double height_m = 0.0;          ///< the beam's height: lower walls are not seen
};

/// The nearest wall point inside a cone.
struct ConeHit {
    std::size_t wall = 0;      ///< index in World::walls
    double distance_m = 0.0;   ///< from the cone's origin
    double incidence_rad = 0.0;///< between the ray to the point and the wall's normal
    Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
};
/// The nearest point of any wall inside `cone` (within its angle, range and
/// height) that the wall's incidence lets echo; none when no wall does.
/// Each wall is taken at its own nearest point inside the cone: a wall whose
/// nearest point is struck beyond max_incidence_rad gives no echo, and a
/// farther wall may.
std::optional<ConeHit> cast_cone(const World& world, const Cone& cone);

/// The distance from `p` to the nearest wall [m]; infinity without walls.
double nearest_wall_distance(const World& world, const Eigen::Vector2d& p);

}  // namespace ddmr::plant
