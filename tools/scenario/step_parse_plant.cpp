// The steps that check or wait on the robot's motion (step_parsers.hpp): expect-pose,
// expect-compare, expect-encoders, wait-until, expect.
#include "scenario/step_parsers.hpp"

namespace ddmr::tools::scenario::yaml {

std::optional<StepAction> parse_plant_step(const std::string& kind, const Ctx& c) {
    if (kind == "expect-pose") {
        c.keys({"source", "x_m", "y_m", "tol_m", "theta_rad", "tol_rad"}, {"x_m", "y_m", "tol_m"});
        ExpectPose p;
        if (c.has("source")) {
            const std::string s = c.child("source").str();
            if (s == "truth") p.source = PoseSource::kTruth;
            else if (s == "firmware") p.source = PoseSource::kFirmware;
            else c.child("source").fail(fmt::format("'{}' is not truth or firmware", s));
        }
        p.x_m = c.child("x_m").number();
        p.y_m = c.child("y_m").number();
        p.tol_m = c.child("tol_m").number_in(0, 100, "[0, 100] m");
        if (c.has("theta_rad")) {
            p.theta_rad = c.child("theta_rad").number();
            if (!c.has("tol_rad")) c.fail("theta_rad needs tol_rad");
            p.tol_rad = c.child("tol_rad").number_in(0, 100, "[0, 100] rad");
        }
        return p;
    }
    if (kind == "expect-compare") {
        c.keys({"case", "max_rms_m", "max_endpoint_m"}, {"max_rms_m"});
        ExpectCompare e;
        if (c.has("case")) e.test_case = c.child("case").integer_in(1, 2);
        e.max_rms_m = c.child("max_rms_m").number_in(0, 100, "[0, 100] m");
        if (c.has("max_endpoint_m")) e.max_endpoint_m = c.child("max_endpoint_m").number_in(0, 100, "[0, 100] m");
        return e;
    }
    if (kind == "expect-encoders") {
        c.keys({"max_lost"}, {"max_lost"});
        return ExpectEncoders{c.child("max_lost").count()};
    }
    if (kind == "wait-until") {
        c.keys({"signal", "op", "value", "timeout"}, {"signal", "value"});
        WaitUntil w;
        w.signal = plant_signal_name(c.child("signal"));
        if (c.has("op")) w.op = compare_op(c.child("op"));
        w.value = c.child("value").number();
        if (c.has("timeout")) w.timeout = c.child("timeout").duration();
        return w;
    }
    if (kind == "measure") {
        c.keys({"signal"}, {"signal"});
        return Measure{plant_signal_name(c.child("signal"))};
    }
    if (kind == "expect-stats") {
        c.keys({"signal", "rms_max", "abs_max", "mean", "range", "min_samples"}, {"signal"});
        ExpectStats e;
        e.signal = plant_signal_name(c.child("signal"));
        if (c.has("rms_max")) e.rms_max = c.child("rms_max").number_in(0, 1e12, "[0, 1e12]");
        if (c.has("abs_max")) e.abs_max = c.child("abs_max").number_in(0, 1e12, "[0, 1e12]");
        if (c.has("mean")) e.mean = min_max_pair(c.child("mean"));
        if (c.has("range")) e.range = min_max_pair(c.child("range"));
        if (c.has("min_samples")) e.min_samples = c.child("min_samples").count();
        if (!e.rms_max && !e.abs_max && !e.mean.set() && !e.range.set()) {
            c.fail("give at least one of rms_max, abs_max, mean, range");
        }
        return e;
    }
    if (kind == "expect") {
        c.keys({"signal", "op", "value", "between"}, {"signal"});
        ExpectSignal e;
        e.signal = plant_signal_name(c.child("signal"));
        if (c.has("between")) {
            if (c.has("op") || c.has("value")) c.fail("give op and value, or between: [min, max], not both");
            e.between = min_max_pair(c.child("between"));
            return e;
        }
        if (!c.has("value")) c.fail("missing required key 'value' (or give between: [min, max])");
        if (c.has("op")) e.op = compare_op(c.child("op"));
        e.value = c.child("value").number();
        return e;
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
