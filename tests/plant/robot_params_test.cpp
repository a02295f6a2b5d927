// Tests for plant/robot_params: defaults are valid, and every parameter is
// rejected when negative, zero where zero is not allowed, NaN or infinite,
// with a message naming "section.key", the value and the valid range.
#include "plant/robot_params.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <variant>

#include "plant/robot.hpp"

namespace ddmr::plant {
namespace {

/// Expects validate(p) to throw a message that contains every `parts`.
void expect_rejected(const RobotParams& p, const std::string& name, const std::string& value) {
    try {
        validate(p);
        ADD_FAILURE() << name << " = " << value << " was accepted";
    } catch (const std::invalid_argument& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find(name), std::string::npos) << msg;
        EXPECT_NE(msg.find(value), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    }
}

TEST(RobotParams, DefaultsAreValid) { EXPECT_NO_THROW(validate(default_robot_params())); }

TEST(RobotParams, EveryInvalidValueIsRejectedByName) {
    int checked = 0;
    const RobotParams defaults = default_robot_params();
    RobotParams probe = defaults;
    for_each_section(probe, [&](const char* section, auto& part, const auto& table) {
        for (const auto& f : table) {
            const std::string name = std::string(section) + "." + f.key;
            std::visit(
                [&](auto m) {
                    using T = std::decay_t<decltype(part.*m)>;
                    const T saved = part.*m;
                    if constexpr (std::is_same_v<T, double>) {
                        part.*m = std::numeric_limits<double>::quiet_NaN();
                        expect_rejected(probe, name, "nan");
                        part.*m = std::numeric_limits<double>::infinity();
                        expect_rejected(probe, name, "inf");
                        part.*m = -1.0;
                        expect_rejected(probe, name, "-1");
                        if (!f.range.contains(0.0)) {
                            part.*m = 0.0;
                            expect_rejected(probe, name, "= 0");
                        }
                        part.*m = 1e9;  // above every upper bound
                        expect_rejected(probe, name, "1000000000");
                        checked += 1;
                    } else if constexpr (std::is_same_v<T, int>) {
                        part.*m = -1;
                        expect_rejected(probe, name, "-1");
                        if (!f.range.contains(0.0)) {
                            part.*m = 0;
                            expect_rejected(probe, name, "= 0");
                        }
                        part.*m = 1000000000;  // above every upper bound
                        expect_rejected(probe, name, "1000000000");
                        checked += 1;
                    }
                    part.*m = saved;
                },
                f.member);
        }
    });
    // 8 motor fields x 2 + 4 bridge fields x 5 chips (driver = L298, tb6612,
    // drv8833, l293d, l9110) + 4 battery + 5 encoder (non-seed) x 2 + 3
    // kinematics + 4 body + 2 integration = 59
    EXPECT_EQ(checked, 59);
    EXPECT_TRUE(probe == defaults);  // every value restored
}

TEST(RobotParams, MessageStatesTheRange) {
    RobotParams p = default_robot_params();
    p.motor[1].resistance_ohm = -2.5;
    try {
        validate(p);
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_STREQ(e.what(),
                     "invalid plant parameter motor2.resistance_ohm = -2.5: must be finite and "
                     "in (0, 1000] ohm");
    }
}

TEST(RobotParams, OddEncoderEdgeCountIsRejected) {
    RobotParams p = default_robot_params();
    p.encoder[0].edges_per_motor_rev = 9;
    expect_rejected(p, "encoder1.edges_per_motor_rev", "9");
}

TEST(RobotParams, EncoderResolutionIsExactlyOneOfTwoKeys) {
    RobotParams p = default_robot_params();
    p.encoder[1].edges_per_wheel_rev = 40.0;  // beside the default 8 per motor turn
    expect_rejected(p, "encoder2.edges_per_wheel_rev", "= 40");
    p.encoder[1].edges_per_motor_rev = 0;  // 40 per wheel turn only: valid
    EXPECT_NO_THROW(validate(p));
    p.encoder[1].edges_per_wheel_rev = 0.0;  // neither
    expect_rejected(p, "encoder2.edges_per_motor_rev", "= 0");
}

TEST(RobotParams, BoardSetFieldsAreValidatedAndCompared) {
    RobotParams p = default_robot_params();
    p.encoder[0].channels = 2;
    EXPECT_NO_THROW(validate(p));
    EXPECT_FALSE(p == default_robot_params());
    p.encoder[0].channels = 0;
    expect_rejected(p, "encoder1.channels", "= 0");
    p = default_robot_params();
    p.chip[1] = DriverChip::drv8833;
    EXPECT_FALSE(p == default_robot_params());
    p.chip[1] = static_cast<DriverChip>(7);
    expect_rejected(p, "chip[1]", "7");
}

TEST(RobotParams, EachMotorGetsItsChipsBridgeParameters) {
    RobotParams p = default_robot_params();
    EXPECT_EQ(&bridge_params(p, 0), &p.driver);  // the thesis's L298 shield
    EXPECT_EQ(&bridge_params(p, 1), &p.driver);
    p.chip = {DriverChip::tb6612, DriverChip::drv8833};
    EXPECT_EQ(&bridge_params(p, 0), &p.tb6612);
    EXPECT_EQ(&bridge_params(p, 1), &p.drv8833);
    EXPECT_EQ(bridge_params(p, 1).on_resistance_ohm, 0.36);
    p.chip[1] = DriverChip::l293d;
    EXPECT_EQ(&bridge_params(p, 1), &p.l293d);
    EXPECT_EQ(bridge_params(p, 1).drop_V, 2.6);
}

TEST(RobotParams, EachChipsSectionNameIsTheSectionItsParametersAreReadFrom) {
    // params_section() names, for `ddmr-hil parts`, the plant-file section
    // whose fields are the chip's bridge_params().
    RobotParams p = default_robot_params();
    for (const DriverChip chip : {DriverChip::l298, DriverChip::tb6612, DriverChip::drv8833, DriverChip::l293d}) {
        p.chip[0] = chip;
        const void* read_from = nullptr;
        for_each_section(p, [&](const char* name, auto& part, const auto& /*fields*/) {
            if (std::string(name) == params_section(chip)) read_from = &part;
        });
        EXPECT_EQ(read_from, &bridge_params(p, 0)) << params_section(chip);
    }
}

TEST(RobotParams, RobotConstructorValidates) {
    RobotParams p = default_robot_params();
    p.kinematics.half_axle_m = 0.0;
    EXPECT_THROW(Robot{p}, std::invalid_argument);
}

TEST(RobotParams, DefaultsDifferPerMotorOnlyWhereTable2Does) {
    const RobotParams p = default_robot_params();
    EXPECT_EQ(p.motor[0].resistance_ohm, 5.32);  // Table 2 R_a1
    EXPECT_EQ(p.motor[1].resistance_ohm, 5.41);  // Table 2 R_a2
    EXPECT_EQ(p.motor[0].gear_ratio, 48.0);
    EXPECT_NE(p.encoder[0].seed, p.encoder[1].seed);
}

}  // namespace
}  // namespace ddmr::plant
