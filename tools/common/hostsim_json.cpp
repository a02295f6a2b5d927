#include "common/hostsim_json.hpp"

namespace ddmr::tools {

namespace hs = ddmr::hostsim;

nlohmann::json gains_json(const hs::Gains& g) {
    return {{"kx", g.kx}, {"ky", g.ky}, {"kw", g.kw}, {"vref_m_s", g.vref_m_s}, {"wref_rad_s", g.wref_rad_s}};
}

nlohmann::json case_json(const hs::CaseSpec& c) {
    nlohmann::json j;
    j["name"] = c.name;
    if (c.kind == hs::CaseKind::circle) {
        j["kind"] = "circle";
        j["radius_m"] = c.radius_m;
        j["rate_rad_s"] = c.rate_rad_s;
        j["heading0_rad"] = c.heading0_rad;
    } else {
        j["kind"] = "line_step";
        j["line_speed_m_s"] = c.line_speed_m_s;
        j["step_m"] = c.step_m;
        j["step_time_s"] = c.step_time_s;
        j["step_axis"] = c.step_axis == hs::StepAxis::x ? "x" : "y";
    }
    j["duration_s"] = c.duration_s;
    return j;
}

}  // namespace ddmr::tools
