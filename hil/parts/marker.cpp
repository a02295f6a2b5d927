// A marker: a named point on the chassis with no pins, for truth.csv and the
// scenarios (docs/world.md, "Truth columns"): the nearest line's centreline
// across the robot's heading from that point (positive to the left; 0 in a
// world without lines) and the floor's reflectance there. A line follower's
// scenario bounds the offset under the middle of its sensor row, where the
// sketch steers to, rather than under the wheel axle, which cuts corners.

#include <memory>

#include "hil/parts/builtin_parts.hpp"
#include "hil/parts/sensor_mount.hpp"

namespace ddmr::hil {
namespace {

class Marker final : public Part {
public:
    explicit Marker(const PartContext& ctx)
        : pose_(ctx.pose_source()), world_(ctx.world()), mount_(mount_of(ctx, false)), none_(ctx.name()) {}

    const LogicSignal& output(const std::string& /*port*/) const override { return none_; }
    std::vector<std::string> truth_columns() const override { return {"line_offset_m", "reflectance"}; }
    void truth_values(std::vector<double>& out) const override {
        const plant::Pose pose = pose_();
        const Eigen::Vector2d at = world_point(pose, mount_);
        const std::optional<plant::LineOffset> line = plant::line_offset(world_, at, pose.theta_rad);
        out.push_back(line ? line->lateral_m : 0.0);
        out.push_back(plant::reflectance_at(world_, at));
    }

private:
    std::function<plant::Pose()> pose_;
    const plant::World& world_;
    SensorMount mount_;
    DrivenSignal none_;
};

}  // namespace

PartType marker_type() {
    PartType t;
    t.type = "marker";
    t.summary = "a named point on the chassis: the line's lateral offset and the floor's reflectance under it (truth only)";
    t.datasheet = "none: a measuring point of the simulation";
    t.keys = mount_keys("the point's", false, 0);
    t.create = [](const PartContext& ctx) { return std::make_unique<Marker>(ctx); };
    return t;
}

}  // namespace ddmr::hil
