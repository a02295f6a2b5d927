// Plant parameters by file key: the key a plant YAML file uses reaches the
// same field, every real-valued field has one, and integers are not offered.
#include "plant/param_access.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include "plant/params_yaml.hpp"

namespace ddmr::plant {
namespace {

TEST(ParamAccess, AKeyReachesItsField) {
    RobotParams p = default_robot_params();
    const auto r = find_param(p, "motor2.resistance_ohm");
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->value, &p.motor[1].resistance_ohm);
    EXPECT_DOUBLE_EQ(*r->value, 5.41);  // Table 2
    EXPECT_STREQ(r->unit, "ohm");
    EXPECT_FALSE(r->range.contains(0.0));
    const auto drop = find_param(p, "driver.drop_V");
    ASSERT_TRUE(drop.has_value());
    EXPECT_EQ(drop->value, &p.driver.drop_V);
}

TEST(ParamAccess, UnknownKeysAndIntegerFieldsAreNotFound) {
    RobotParams p = default_robot_params();
    EXPECT_FALSE(find_param(p, "motor3.resistance_ohm"));
    EXPECT_FALSE(find_param(p, "motor1"));
    EXPECT_FALSE(find_param(p, "encoder1.edges_per_motor_rev"));  // int
    EXPECT_FALSE(find_param(p, "encoder1.seed"));                 // uint64
}

TEST(ParamAccess, EveryKeyIsFoundAndWritingItChangesTheYaml) {
    const std::vector<std::string> keys = param_keys();
    EXPECT_GT(keys.size(), 30u);
    EXPECT_NE(std::find(keys.begin(), keys.end(), "kinematics.half_axle_m"), keys.end());
    EXPECT_EQ(std::find(keys.begin(), keys.end(), "encoder1.seed"), keys.end());
    const std::string defaults = emit_robot_params(default_robot_params());
    for (const std::string& k : keys) {
        RobotParams p = default_robot_params();
        const auto r = find_param(p, k);
        ASSERT_TRUE(r.has_value()) << k;
        EXPECT_EQ(r->key, k);
        *r->value = *r->value * 0.5 + 0.0123;  // any other value
        EXPECT_NE(emit_robot_params(p), defaults) << k;  // the field behind the key is the file's
    }
}

}  // namespace
}  // namespace ddmr::plant
