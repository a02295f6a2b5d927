#include "hil/world_truth.hpp"

namespace ddmr::hil {

WorldTruth::WorldTruth(const plant::World& world, std::function<plant::Pose()> pose)
    : world_(world), pose_(std::move(pose)) {
    if (!world_.lines.empty()) columns_.emplace_back("line_offset_m");
    if (!world_.walls.empty()) columns_.emplace_back("wall_distance_m");
}

void WorldTruth::values(std::vector<double>& out) const {
    if (columns_.empty()) return;
    const plant::Pose p = pose_();
    const Eigen::Vector2d at(p.x_m, p.y_m);
    if (!world_.lines.empty()) out.push_back(plant::line_offset(world_, at, p.theta_rad)->lateral_m);
    if (!world_.walls.empty()) out.push_back(plant::nearest_wall_distance(world_, at));
}

}  // namespace ddmr::hil
