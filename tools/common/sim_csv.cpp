#include "common/sim_csv.hpp"

#include <fmt/format.h>

#include <iterator>

#include "common/truth_csv.hpp"

namespace ddmr::tools {

namespace hs = ddmr::hostsim;

std::string sim_csv(const hs::SimResult& r) {
    std::string csv = truth_csv_header(/*with_drive=*/true);
    csv.pop_back();  // the header's newline
    csv += ",goal_x_m,goal_y_m,lyapunov\n";
    csv.reserve(csv.size() + r.samples.size() * 200);
    for (const hs::SimSample& s : r.samples) {
        hil::TruthSample t;
        t.t_s = s.t_s;
        t.x_m = s.x_m;
        t.y_m = s.y_m;
        t.theta_rad = s.theta_rad;
        t.v_m_s = s.v_m_s;
        t.omega_rad_s = s.omega_rad_s;
        t.ia1_A = s.ia1_A;
        t.ia2_A = s.ia2_A;
        t.wheel1_rad_s = s.wheel1_rad_s;
        t.wheel2_rad_s = s.wheel2_rad_s;
        t.vbatt_V = s.vbatt_V;
        t.edges1 = s.edges1;
        t.edges2 = s.edges2;
        t.duty1 = s.duty1;
        t.duty2 = s.duty2;
        t.dir1 = s.dir1;
        t.dir2 = s.dir2;
        append_truth_row(csv, t, /*with_drive=*/true);
        csv.pop_back();
        fmt::format_to(std::back_inserter(csv), ",{:.9g},{:.9g},{:.9g}\n", s.goal_x_m, s.goal_y_m, s.lyapunov);
    }
    return csv;
}

}  // namespace ddmr::tools
