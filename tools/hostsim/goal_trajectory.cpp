#include "tools/hostsim/goal_trajectory.hpp"

#include <stdexcept>
#include <string>

#include "plant/units.hpp"
#include "tools/hostsim/firmware_constants.hpp"

namespace ddmr::hostsim {

namespace {

void require(bool ok, const std::string& field, double value, const char* range) {
    if (!ok) {
        throw std::invalid_argument("case " + field + " = " + std::to_string(value) + ": must be " + range);
    }
}

}  // namespace

CaseSpec firmware_case(int case_number) {
    CaseSpec c;
    c.kind = CaseKind::circle;
    c.heading0_rad = firmware::kInitialHeading_rad;
    if (case_number == 1) {
        c.name = "case1";
        c.radius_m = firmware::kCase1Radius_m;
        c.rate_rad_s = firmware::kCase1Rate_rad_s;
        c.duration_s = firmware::kCase1Duration_s;
        c.logs_eeprom = true;
    } else if (case_number == 2) {
        c.name = "case2";
        c.radius_m = firmware::kCase2Radius_m;
        c.rate_rad_s = firmware::kCase2Rate_rad_s;
        c.duration_s = firmware::kCase2Duration_s;
        c.logs_eeprom = false;  // the sketch's case 2 loop has no EEPROM.write
    } else {
        throw std::invalid_argument("case " + std::to_string(case_number) +
                                    ": the firmware has cases 1 and 2 only");
    }
    return c;
}

CaseSpec circle_case(double radius_m, double period_s) {
    require(radius_m > 0.0 && radius_m <= 100.0, "radius", radius_m, "in (0, 100] m");
    require(period_s > 0.0 && period_s <= 3600.0, "period", period_s, "in (0, 3600] s");
    CaseSpec c;
    c.name = "circle";
    c.kind = CaseKind::circle;
    c.radius_m = radius_m;
    c.rate_rad_s = 2.0 * plant::kPi / period_s;
    c.heading0_rad = plant::kPi / 2.0;
    c.duration_s = period_s;
    c.logs_eeprom = true;
    return c;
}

CaseSpec line_step_case(StepAxis axis) {
    CaseSpec c;
    c.name = axis == StepAxis::x ? "line-x" : "line-y";
    c.kind = CaseKind::line_step;
    c.rate_rad_s = 0.0;
    c.heading0_rad = 0.0;
    c.line_speed_m_s = 0.5;
    c.step_m = 0.2;
    c.step_time_s = 10.0;
    c.step_axis = axis;
    c.duration_s = 20.0;
    c.logs_eeprom = true;
    return c;
}

void validate(const CaseSpec& c) {
    require(c.duration_s > 0.0 && c.duration_s <= 3600.0, "duration_s", c.duration_s, "in (0, 3600] s");
    if (c.kind == CaseKind::circle) {
        require(c.radius_m > 0.0 && c.radius_m <= 100.0, "radius_m", c.radius_m, "in (0, 100] m");
        require(std::isfinite(c.rate_rad_s), "rate_rad_s", c.rate_rad_s, "finite");
        require(std::isfinite(c.heading0_rad), "heading0_rad", c.heading0_rad, "finite");
    } else {
        require(c.line_speed_m_s >= 0.0 && c.line_speed_m_s <= 10.0, "line_speed_m_s",
                c.line_speed_m_s, "in [0, 10] m/s");
        require(std::abs(c.step_m) <= 10.0, "step_m", c.step_m, "in [-10, 10] m");
        require(c.step_time_s >= 0.0, "step_time_s", c.step_time_s, ">= 0 s");
    }
}

GoalVelocity goal_velocity(const CaseSpec& c) {
    if (c.kind == CaseKind::circle) return {c.radius_m * c.rate_rad_s, c.rate_rad_s};
    return {c.line_speed_m_s, 0.0};
}

}  // namespace ddmr::hostsim
