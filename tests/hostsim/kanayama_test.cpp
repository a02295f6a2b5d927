#include "tools/hostsim/kanayama.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace ddmr::hostsim {
namespace {

// The sketch's first iteration of case 1: the robot at the origin heading 0,
// the goal at (0.6, 0) heading Angref = 1.571.
//   eq. (12): errxr = 0.6, erryr = 0, etheta = 1.571
//   cos(1.571) = -sin(1.571 - pi/2) = -2.0367e-4,  sin(1.571) = 0.99999998
//   eq. (14) with kx = 1 (the sketch's int): v = 0.2 x -2.0367e-4 + 1 x 0.6 = 0.5999593
//                                            w = 0.2 + 0.2 (6 x 0 + 8 x 0.99999998) = 1.8
TEST(Kanayama, FirmwaresFirstIterationByHand) {
    const Gains g = integer_gains(Gains{});
    for (int pass = 0; pass < 2; ++pass) {
        double v = 0.0, w = 0.0;
        if (pass == 0) {
            const TrackingError<double> e = tracking_error(0.6, 0.0, 1.571, PoseEstimate<double>{0.0, 0.0, 0.0});
            EXPECT_DOUBLE_EQ(e.x_m, 0.6);
            EXPECT_DOUBLE_EQ(e.y_m, 0.0);
            EXPECT_DOUBLE_EQ(e.theta_rad, 1.571);
            const VelocityCommand<double> c = kanayama_law(e, g);
            v = c.v_m_s;
            w = c.omega_rad_s;
        } else {  // float, as on the robot
            const TrackingError<float> e =
                tracking_error(0.6F, 0.0F, 1.571F, PoseEstimate<float>{0.0F, 0.0F, 0.0F});
            const VelocityCommand<float> c = kanayama_law(e, g);
            v = static_cast<double>(c.v_m_s);
            w = static_cast<double>(c.omega_rad_s);
        }
        EXPECT_NEAR(v, 0.59996, 1e-5) << "pass " << pass;
        EXPECT_NEAR(v, 0.6 - 0.2 * 2.0367e-4, 1e-7) << "pass " << pass;
        EXPECT_NEAR(w, 1.8, 1e-6) << "pass " << pass;
    }
    // With the thesis's intended kx = 1.1: v = 0.66 - 4.07e-5.
    const VelocityCommand<double> c =
        kanayama_law(tracking_error(0.6, 0.0, 1.571, PoseEstimate<double>{0, 0, 0}), Gains{});
    EXPECT_NEAR(c.v_m_s, 0.66 - 0.2 * 2.0367e-4, 1e-7);
}

TEST(Kanayama, ErrorIsInTheRobotFrame) {
    // Robot at (1, 1) heading +y (pi/2); goal at (1, 2): 1 m straight ahead.
    const double half_pi = 1.5707963267948966;
    const TrackingError<double> e = tracking_error(1.0, 2.0, half_pi, PoseEstimate<double>{1.0, 1.0, half_pi});
    EXPECT_NEAR(e.x_m, 1.0, 1e-15);
    EXPECT_NEAR(e.y_m, 0.0, 1e-15);
    EXPECT_DOUBLE_EQ(e.theta_rad, 0.0);
    // Goal at (0, 1): 1 m to the robot's left.
    const TrackingError<double> l = tracking_error(0.0, 1.0, half_pi, PoseEstimate<double>{1.0, 1.0, half_pi});
    EXPECT_NEAR(l.x_m, 0.0, 1e-15);
    EXPECT_NEAR(l.y_m, 1.0, 1e-15);
}

TEST(Kanayama, IntegerGainsTruncateAsConstIntDoes) {
    const Gains g = integer_gains(Gains{1.1, 6.0, 8.0, 0.2, 0.2});
    EXPECT_EQ(g.kx, 1.0);  // `const int kx=1.1;`
    EXPECT_EQ(g.ky, 6.0);
    EXPECT_EQ(g.kw, 8.0);
    EXPECT_EQ(g.vref_m_s, 0.2);  // floats in the sketch: unchanged
    const Gains h = integer_gains(Gains{2.9, 6.5, 0.4, 0.3, 0.3});
    EXPECT_EQ(h.kx, 2.0);
    EXPECT_EQ(h.ky, 6.0);
    EXPECT_EQ(h.kw, 0.0);
}

TEST(Kanayama, LyapunovFunctionByHand) {
    // eq. (15) at the first iteration: 0.5 x 0.36 + (1 - cos 1.571) / 6 = 0.18 + 1.0000204 / 6 = 0.3466701
    const TrackingError<double> e{0.6, 0.0, 1.571};
    EXPECT_NEAR(lyapunov(e, 6.0), 0.18 + (1.0 + 2.0367e-4) / 6.0, 1e-8);
    EXPECT_TRUE(std::isnan(lyapunov(e, 0.0)));
    // eq. (16): -1.1 x 0.36 - 0.2 x 8 x sin^2(1.571) / 6 = -0.396 - 0.2666667
    EXPECT_NEAR(lyapunov_rate(e, Gains{}), -0.396 - 1.6 / 6.0, 1e-7);
}

TEST(Kanayama, ValidateNamesTheGain) {
    EXPECT_NO_THROW(validate(Gains{}));
    try {
        validate(Gains{1.1, -6.0, 8.0, 0.2, 0.2});
        FAIL();
    } catch (const std::invalid_argument& e) {
        EXPECT_EQ(std::string(e.what()).rfind("ky", 0), 0U) << e.what();
    }
    EXPECT_THROW(validate(Gains{std::nan(""), 6.0, 8.0, 0.2, 0.2}), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::hostsim
