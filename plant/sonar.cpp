#include "plant/sonar.hpp"

#include <algorithm>

namespace ddmr::plant {

double speed_of_sound_m_s(double temperature_c) { return 331.5 + 0.6 * temperature_c; }

std::optional<double> sonar_distance_m(const World& world, const SonarParams& p, const Eigen::Vector2d& origin_m,
                                       double direction_rad) {
    Cone cone;
    cone.origin_m = origin_m;
    cone.direction_rad = direction_rad;
    cone.half_angle_rad = p.cone_full_angle_rad / 2.0;
    cone.max_incidence_rad = p.max_incidence_rad;
    cone.max_range_m = p.max_range_m;
    cone.height_m = p.mount_height_m;
    const std::optional<ConeHit> hit = cast_cone(world, cone);
    if (!hit) return std::nullopt;
    return std::max(hit->distance_m, p.min_range_m);
}

double echo_width_s(const SonarParams& p, std::optional<double> distance_m) {
    if (!distance_m) return p.no_echo_s;
    return 2.0 * *distance_m / speed_of_sound_m_s(p.temperature_c);
}

}  // namespace ddmr::plant
