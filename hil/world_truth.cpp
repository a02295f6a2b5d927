#include "hil/world_truth.hpp"

namespace ddmr::hil {

WorldTruth::WorldTruth(const plant::World& world, const plant::Robot& robot) : world_(world), robot_(robot) {
    if (!world_.lines.empty()) columns_.emplace_back("line_offset_m");
    if (!world_.walls.empty()) {
        for (const char* c : {"wall_distance_m", "contact", "contacts"}) columns_.emplace_back(c);
    }
}

void WorldTruth::values(std::vector<double>& out) const {
    if (columns_.empty()) return;
    const plant::Pose p = robot_.pose();
    const Eigen::Vector2d at(p.x_m, p.y_m);
    if (!world_.lines.empty()) out.push_back(plant::line_offset(world_, at, p.theta_rad)->lateral_m);
    if (world_.walls.empty()) return;
    out.push_back(plant::nearest_wall_distance(world_, at));
    out.push_back(robot_.in_contact() ? 1.0 : 0.0);
    out.push_back(static_cast<double>(robot_.contact_count()));
}

}  // namespace ddmr::hil
