#include "common/truth_csv.hpp"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <iterator>

namespace ddmr::tools {

std::string truth_csv_header(bool with_drive) {
    std::string h =
        "t_s,x_m,y_m,theta_rad,v_m_s,omega_rad_s,ia1_A,ia2_A,wheel1_rad_s,wheel2_rad_s,vbatt_V,"
        "edges1,edges2";
    if (with_drive) h += ",duty1,duty2,dir1,dir2";
    return h + "\n";
}

void append_truth_row(std::string& out, const hil::TruthSample& s, bool with_drive) {
    auto it = std::back_inserter(out);
    fmt::format_to(it, FMT_COMPILE("{:.6f},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{},{}"),
                   s.t_s, s.x_m, s.y_m, s.theta_rad, s.v_m_s, s.omega_rad_s, s.ia1_A, s.ia2_A,
                   s.wheel1_rad_s, s.wheel2_rad_s, s.vbatt_V, s.edges1, s.edges2);
    if (with_drive) {
        fmt::format_to(it, FMT_COMPILE(",{:.6f},{:.6f},{},{}"), s.duty1, s.duty2, s.dir1 ? 1 : 0, s.dir2 ? 1 : 0);
    }
    out.push_back('\n');
}

void append_truth_values(std::vector<double>& out, const hil::TruthSample& s, bool with_drive) {
    out.insert(out.end(), {s.t_s, s.x_m, s.y_m, s.theta_rad, s.v_m_s, s.omega_rad_s, s.ia1_A, s.ia2_A,
                           s.wheel1_rad_s, s.wheel2_rad_s, s.vbatt_V, static_cast<double>(s.edges1),
                           static_cast<double>(s.edges2)});
    if (with_drive) out.insert(out.end(), {s.duty1, s.duty2, s.dir1 ? 1.0 : 0.0, s.dir2 ? 1.0 : 0.0});
}

}  // namespace ddmr::tools
