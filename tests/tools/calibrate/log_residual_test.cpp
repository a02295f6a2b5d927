// The log's cells worked out by hand: int() truncates toward zero, the byte
// is the low 8 bits, 250 counts per metre (4 mm).
#include "calibrate/log_residual.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace ddmr::calibrate {
namespace {

TEST(CountCell, TruncationTowardZeroMakesZeroTwoCountsWide) {
    EXPECT_DOUBLE_EQ(count_cell(0).lo, -1.0);
    EXPECT_DOUBLE_EQ(count_cell(0).hi, 1.0);
    EXPECT_DOUBLE_EQ(count_cell(3).lo, 3.0);  // int(3.9) = 3
    EXPECT_DOUBLE_EQ(count_cell(3).hi, 4.0);
    EXPECT_DOUBLE_EQ(count_cell(-3).lo, -4.0);  // int(-3.9) = -3
    EXPECT_DOUBLE_EQ(count_cell(-3).hi, -3.0);
}

TEST(CellResidual, ZeroInsideTheCellAndTheDistanceOutside) {
    EXPECT_DOUBLE_EQ(cell_residual_m(0.0, 0), 0.0);
    EXPECT_DOUBLE_EQ(cell_residual_m(0.003, 0), 0.0);   // 0.75 counts: int = 0
    EXPECT_DOUBLE_EQ(cell_residual_m(-0.003, 0), 0.0);  // -0.75 counts: int = 0
    EXPECT_DOUBLE_EQ(cell_residual_m(0.005, 1), 0.0);   // 1.25 counts: int = 1
    // 1.25 counts against byte 0: 0.25 counts past the cell (-1, 1) = 1 mm.
    EXPECT_NEAR(cell_residual_m(0.005, 0), 0.001, 1e-15);
    // 0.1 m = 25 counts against byte 20 (cell [20, 21)): 4 counts = 16 mm.
    EXPECT_NEAR(cell_residual_m(0.1, 20), 0.016, 1e-15);
}

TEST(CellResidual, NegativeValuesAndWrapAroundNeedNoUnwrapping) {
    // -1.25 counts: int = -1, whose low byte is 255.
    EXPECT_DOUBLE_EQ(cell_residual_m(-0.005, 255), 0.0);
    // -0.4 m = -100 counts: int = -100 = 156 (mod 256).
    EXPECT_DOUBLE_EQ(cell_residual_m(-0.4, 156), 0.0);
    // 1.042 m = 260.5 counts: int = 260 = 4 (mod 256).
    EXPECT_DOUBLE_EQ(cell_residual_m(1.042, 4), 0.0);
    // Byte 200 seen from 0 m: the cell of -56 ((-57, -56]) is 56 counts away,
    // nearer than 200's [200, 201).
    EXPECT_NEAR(cell_residual_m(0.0, 200), 56.0 / 250.0, 1e-15);
}

TEST(CellResidual, ADivergedRunIsFarAndNotANumberIsInfinitelyFar) {
    EXPECT_NEAR(cell_residual_m(3e10, 0), 3e10, 1.0);
    EXPECT_TRUE(std::isinf(cell_residual_m(std::nan(""), 0)));
}

// Byte 1 is the cell [1, 2) counts, centre 1.5 (6 mm); byte 255 next to 0
// is c = -1, the cell (-2, -1], centre -1.5; byte 0 is (-1, 1), centre 0;
// the nearest repeat of byte 1 from 1.03 m (257.5 counts) is c = 257.
TEST(CellCentreResidual, SignedDistanceToTheNearestCellsCentre) {
    EXPECT_NEAR(cell_centre_residual_m(0.0041, 1), (1.025 - 1.5) / 250.0, 1e-12);
    EXPECT_NEAR(cell_centre_residual_m(0.0070, 1), (1.75 - 1.5) / 250.0, 1e-12);
    EXPECT_NEAR(cell_centre_residual_m(-0.005, 255), (-1.25 + 1.5) / 250.0, 1e-12);
    EXPECT_NEAR(cell_centre_residual_m(0.002, 0), 0.002, 1e-12);
    EXPECT_NEAR(cell_centre_residual_m(1.03, 1), (257.5 - 257.5) / 250.0, 1e-12);
    EXPECT_TRUE(std::isinf(cell_centre_residual_m(std::nan(""), 0)));
}

TEST(SoftL1, QuadraticNearZeroLinearFarAway) {
    EXPECT_DOUBLE_EQ(soft_l1(0.0, 0.004), 0.0);
    EXPECT_NEAR(soft_l1(1e-6, 0.004), 1e-12, 1e-18);  // r^2
    EXPECT_NEAR(soft_l1(0.004, 0.004), 2 * 0.004 * 0.004 * (std::sqrt(2.0) - 1.0), 1e-18);
    // Far out: 2 s |r| - 2 s^2 + O(s^3/r).
    EXPECT_NEAR(soft_l1(1.0, 0.004), 2 * 0.004 * 1.0 - 2 * 0.004 * 0.004, 1e-7);
    EXPECT_DOUBLE_EQ(soft_l1(-0.01, 0.004), soft_l1(0.01, 0.004));
    EXPECT_THROW(soft_l1(1.0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace ddmr::calibrate
