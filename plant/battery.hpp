#pragma once
// Battery pack: 4 alkaline AA cells in series (thesis ch. 5, eqs. 18, 19).
//
//   eq. (18)  AH_new = AH_old - dt (I_1 + I_2) / 3600       (charge drawn)
//   eq. (19)  V_b    = V_0 - k (AH_0 - AH) - R_b (I_1 + I_2)
//
// written here with the charge drawn q [C] as the state (dq/dt = I_supply) and
// the supply current I_supply of both bridges (negative while a bridge returns
// current through its flyback diodes).
//
// (params, BatteryState, I_supply) => terminal voltage; dq/dt = I_supply.

#include <array>

#include "plant/param_spec.hpp"
#include "plant/units.hpp"

namespace ddmr::plant {

struct BatteryParams {
    double open_circuit_V = 6.1;          ///< V_0, full pack [V], (0, 50]. MATLAB listing / firmware Batt = 1/6.1.
    double capacity_Ah = 2.5;             ///< AH_0 [Ah], (0, 100]. MATLAB listing.
    double internal_resistance_ohm = 0.037;  ///< R_b [ohm], [0, 10]. MATLAB listing.
    double sag_V_per_Ah = 0.72;           ///< k in eq. (19) [V/Ah], [0, 10]. Eq. (19).
};

const std::array<Field<BatteryParams>, 4>& battery_fields();
void validate(const BatteryParams& p, const char* prefix);

struct BatteryState {
    double charge_drawn_C = 0.0;  ///< q: charge taken from the pack since full [C]
};

/// eq. (19) without the R_b term: the pack's source voltage V_0 - k AH [V].
double source_voltage_V(const BatteryParams& p, const BatteryState& s);

/// eq. (19): terminal voltage [V] at charge drawn q and supply current I, never below 0.
double terminal_voltage_V(const BatteryParams& p, const BatteryState& s, double supply_current_A);

/// eq. (18) as a derivative: dq/dt = I_supply [A].
inline double charge_derivative_A(double supply_current_A) { return supply_current_A; }

/// Remaining fraction of the capacity, 1 when full (may go below 0).
double state_of_charge(const BatteryParams& p, const BatteryState& s);

}  // namespace ddmr::plant
