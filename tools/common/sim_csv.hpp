#pragma once
// sim.csv: the host simulation's samples in truth.csv's columns (with the
// drive), plus the goal and the Lyapunov function (eq. 15).
#include <string>

#include "tools/hostsim/host_sim.hpp"

namespace ddmr::tools {

std::string sim_csv(const hostsim::SimResult& result);

}  // namespace ddmr::tools
