#pragma once
// How far a simulated run is from a logged one, respecting how the log was
// made (issue 18): the reference sketch stores each coordinate as
// EEPROM.write(addr, int(E * 250.0)), the low 8 bits of a value truncated
// toward zero. A logged byte b therefore stands for every E with
// int(E * 250) = c and c = b (mod 256): a cell 4 mm wide, repeated every
// 1.024 m. The residual of a simulated E is its distance to the nearest such
// cell (0 inside it): a fit is not pulled toward a cell's edge, and a run
// whose bytes wrap (E negative, or 1.024 m and more) needs no unwrapping of
// the log, nor the ambiguity of unwrapping a jump of more than 0.512 m.
//
// int() truncates toward zero (C++ [conv.fpint]): c > 0 covers [c, c + 1)
// counts, c < 0 covers (c - 1, c], and c = 0 covers (-1, 1), two counts wide.

#include <cstdint>

namespace ddmr::calibrate {

/// Counts per metre of the reference sketch's log (int(E * 250.0)).
inline constexpr double kLogCountsPerMetre = 250.0;

/// The closed interval of E * counts_per_m that int() maps to `c`.
struct CountCell {
    double lo = 0.0;
    double hi = 0.0;
};
CountCell count_cell(long long c);

/// Distance [m] from `sim_m` to the nearest cell of `byte`: 0 when
/// int(sim_m * 250) has the low byte `byte`.
double cell_residual_m(double sim_m, uint8_t byte, double counts_per_m = kLogCountsPerMetre);

/// Signed distance [m] from `sim_m` to the centre of the nearest cell of
/// `byte` (a least-squares residual: smooth across the cell, where
/// cell_residual_m is flat).
double cell_centre_residual_m(double sim_m, uint8_t byte, double counts_per_m = kLogCountsPerMetre);

/// The soft-L1 (pseudo-Huber) loss of a residual r at scale s > 0:
/// 2 s^2 (sqrt(1 + (r/s)^2) - 1). Quadratic (r^2) for |r| << s, linear
/// (2 s |r|) for |r| >> s: a few bad samples (a wheel slip, a bumped robot)
/// do not dominate the fit.
double soft_l1(double r, double s);

}  // namespace ddmr::calibrate
