#include "hil/parts/sensor_mount.hpp"

#include <fmt/format.h>

#include <cmath>

#include "plant/units.hpp"

namespace ddmr::hil {

std::vector<PartKey> mount_keys(const std::string& what, bool directional, double default_x_mm) {
    std::vector<PartKey> keys{
        PartKey::number("x_mm", what + " position ahead of the wheel axle's middle [mm] (behind: negative)",
                        default_x_mm, -1000, 1000),
        PartKey::number("y_mm", what + " position left of the robot's centre line [mm] (right: negative)", 0, -1000,
                        1000),
    };
    if (directional) {
        keys.push_back(PartKey::number("heading_deg",
                                       what + " axis, counter-clockwise from straight ahead [deg] (90: to the left)", 0,
                                       -180, 180));
        keys.push_back(PartKey::carrier(
            "mount", "a servo part it sits on: it then turns with the horn, at the servo's x_mm, y_mm and heading_deg "
                     "(its own left out); left out: fixed on the chassis"));
    }
    return keys;
}

std::optional<PartKeyProblem> check_mount(const PartEntry& e) {
    const auto mount = e.values.find("mount");
    if (mount == e.values.end() || mount->second.text.empty()) return std::nullopt;
    for (const char* key : {"x_mm", "y_mm", "heading_deg"}) {
        const auto it = e.values.find(key);
        if (it != e.values.end() && it->second.line != 0) {
            return PartKeyProblem{key, fmt::format("not with mount: {}: the servo's horn sets where the sensor is "
                                                   "(set the servo's x_mm, y_mm, heading_deg)",
                                                   mount->second.text)};
        }
    }
    return std::nullopt;
}

SensorPlacement::SensorPlacement(const PartContext& ctx) : fixed_(mount_of(ctx, true)), carrier_(ctx.carrier("mount")) {}

SensorMount mount_of(const PartContext& ctx, bool directional) {
    SensorMount m;
    m.x_m = ctx.number("x_mm") * 1e-3;
    m.y_m = ctx.number("y_mm") * 1e-3;
    if (directional) m.heading_rad = ctx.number("heading_deg") * plant::kPi / 180.0;
    return m;
}

Eigen::Vector2d world_point(const plant::Pose& pose, const SensorMount& mount) {
    const double c = std::cos(pose.theta_rad);
    const double s = std::sin(pose.theta_rad);
    return {pose.x_m + c * mount.x_m - s * mount.y_m, pose.y_m + s * mount.x_m + c * mount.y_m};
}

double world_heading_rad(const plant::Pose& pose, const SensorMount& mount) { return pose.theta_rad + mount.heading_rad; }

}  // namespace ddmr::hil
