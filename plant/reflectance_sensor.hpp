#pragma once
// Reflectance (line) sensors: what an IR emitter/phototransistor pair sees of
// the floor under it, and the three outputs kit modules make of it
// (../shared/SENSORS.md section 2):
//   - the spot: the phototransistor collects light from a disc of the floor
//     a few millimetres across (TCRT5000: virtual source 2.1 mm, best at
//     2.5 mm above the floor [TCRT] p. 1; QTR: 3 mm optimum [POL]). Its
//     reflectance is the mean over the disc, taken here at 13 points: the
//     centre, 4 at half the radius and 8 on the rim;
//   - analog (QTR-A [QTRAN] 2009 p. 4, TCRT5000 modules' AO): a voltage
//     linear in reflectance between the module's white and black levels;
//   - digital (LM393 comparator modules [SF], [VEND]): a level, set when the
//     spot is darker than a threshold, with the module's polarity;
//   - RC (QTR-RC [QTRAN] section 2): the line's capacitor, charged by the
//     MCU, discharges through the phototransistor, whose current grows with
//     the light returned: the decay time is 1 / (g0 + g1 * r), fitted to
//     two measured points (white and black; 2009 edition p. 3: 780 us and
//     10 ms at 3/8" above the surface).
// Pure functions of plain parameters; SI units.

#include <Eigen/Core>

#include "plant/world.hpp"

namespace ddmr::plant {

/// The mean reflectance of the floor over a disc of `spot_diameter_m` at `p`
/// (a diameter of 0: the reflectance at `p`).
double spot_reflectance(const World& world, const Eigen::Vector2d& p, double spot_diameter_m);

/// An analog output: `white_v` at kWhiteReflectance, `black_v` at
/// kBlackTapeReflectance, linear in between and beyond, clamped to [0, supply_v].
struct AnalogReflectanceParams {
    double white_v = 0.3;
    double black_v = 4.5;
    double supply_v = 5.0;
};
double analog_output_v(const AnalogReflectanceParams& p, double reflectance);

/// An RC output's decay time over kWhiteReflectance and kBlackTapeReflectance.
struct RcReflectanceParams {
    double white_decay_s = 780e-6;
    double black_decay_s = 10e-3;
};
/// The time [s] the charged line takes to read low over `reflectance`
/// (white_decay_s at white, black_decay_s at black tape; needs
/// black_decay_s > white_decay_s > 0). A floor darker than the tape takes
/// the tape's time: the fit is not extended below the darker of its points.
double rc_decay_s(const RcReflectanceParams& p, double reflectance);

}  // namespace ddmr::plant
