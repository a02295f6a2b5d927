#include "plant/body_contact.hpp"

#include <algorithm>
#include <cmath>

#include "plant/segment_clip.hpp"

namespace ddmr::plant {

const std::array<Field<BodyParams>, 4>& body_fields() {
    using P = BodyParams;
    static const std::array<Field<P>, 4> table{{
        {"front_m", "m", non_negative(10.0), &P::front_m},
        {"rear_m", "m", non_negative(10.0), &P::rear_m},
        {"width_m", "m", positive(10.0), &P::width_m},
        {"slip_at_contact", "1", Range{0.0, 1.0, true, true}, &P::slip_at_contact},
    }};
    return table;
}

void validate(const BodyParams& p, const char* prefix) { validate_fields(p, body_fields(), prefix); }

std::optional<WallContact> body_contact(const World& world, const BodyParams& body, const Pose& pose) {
    const double c = std::cos(pose.theta_rad);
    const double s = std::sin(pose.theta_rad);
    const Eigen::Vector2d origin(pose.x_m, pose.y_m);
    // A point in the robot's frame: x along the heading, y to the left.
    const auto local = [&](const Eigen::Vector2d& p) {
        const Eigen::Vector2d d = p - origin;
        return Eigen::Vector2d(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
    };
    const double half_w = body.width_m / 2.0;
    for (std::size_t i = 0; i < world.walls.size(); ++i) {
        const Wall& w = world.walls[i];
        const Eigen::Vector2d a = local(w.a_m);
        const Eigen::Vector2d d = local(w.b_m) - a;
        double lo = 0.0, hi = 1.0;
        // front - x >= 0, x + rear >= 0, half_w - y >= 0, y + half_w >= 0.
        if (!clip_to_half_plane(body.front_m - a.x(), -d.x(), lo, hi) ||
            !clip_to_half_plane(a.x() + body.rear_m, d.x(), lo, hi) ||
            !clip_to_half_plane(half_w - a.y(), -d.y(), lo, hi) || !clip_to_half_plane(a.y() + half_w, d.y(), lo, hi)) {
            continue;
        }
        WallContact contact;
        contact.wall = i;
        contact.point_m = w.a_m + 0.5 * (lo + hi) * (w.b_m - w.a_m);
        const Eigen::Vector2d along = w.b_m - w.a_m;
        Eigen::Vector2d n(-along.y(), along.x());
        if (n.squaredNorm() > 0.0) n.normalize();
        if (n.dot(origin - contact.point_m) < 0.0) n = -n;
        contact.normal = n;
        return contact;
    }
    return std::nullopt;
}

bool moves_off(const WallContact& contact, const Pose& pose, const BodyVelocity& v) {
    const Eigen::Vector2d heading(std::cos(pose.theta_rad), std::sin(pose.theta_rad));
    const Eigen::Vector2d r = contact.point_m - Eigen::Vector2d(pose.x_m, pose.y_m);
    // The velocity of the body's point at the contact: v heading + omega x r.
    const Eigen::Vector2d point_v = v.v_m_s * heading + v.omega_rad_s * Eigen::Vector2d(-r.y(), r.x());
    return point_v.dot(contact.normal) > 0.0;
}

}  // namespace ddmr::plant
