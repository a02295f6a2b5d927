// The steps that check the firmware's insides (step_parsers.hpp): expect-var,
// expect-eeprom, expect-loop, expect-isr, expect-no-torn-reads.
#include "scenario/step_parsers.hpp"

#include <stdexcept>
#include <vector>

#include "hil/firmware_variables.hpp"

namespace ddmr::tools::scenario::yaml {

std::optional<StepAction> parse_firmware_step(const std::string& kind, const Ctx& c) {
    if (kind == "expect-var") {
        c.keys({"name", "type", "op", "value"}, {"name", "value"});
        ExpectVar v;
        v.name = c.child("name").str();
        if (c.has("type")) {
            try {
                v.type = hil::parse_var_type(c.child("type").str());
            } catch (const std::invalid_argument& e) {
                c.child("type").fail(e.what());
            }
        }
        if (c.has("op")) v.op = compare_op(c.child("op"));
        v.value = c.child("value").number();
        return v;
    }
    if (kind == "expect-eeprom") {
        c.keys({"bin", "log", "tol_m"});
        ExpectEeprom e;
        if (c.has("bin")) e.bin = existing_file(c.child("bin"));
        if (c.has("log")) {
            e.log = existing_file(c.child("log"));
            if (!c.has("tol_m")) c.fail("log needs tol_m");
            e.tol_m = c.child("tol_m").number_in(0, 100, "[0, 100] m");
        }
        if (!e.bin && !e.log) c.fail("give bin (the raw EEPROM, every byte) or log (CSV) with tol_m");
        return e;
    }
    if (kind == "expect-loop") {
        c.keys({"max_us", "p99_us", "mean_us", "period_max_us", "period_p99_us", "period_mean_us",
                "include_eeprom_writes"});
        ExpectLoop l;
        const auto range = [&](const char* k, Range& out) {
            if (!c.has(k)) return;
            const Ctx r = c.child(k);
            if (r.node().IsSequence()) {
                if (r.node().size() != 2) r.fail("expected a bound or [min, max]");
                out.min = r.at(r.node()[0], r.key() + "[0]").number_in(0, 1e9, "[0, 1e9] us");
                out.max = r.at(r.node()[1], r.key() + "[1]").number_in(0, 1e9, "[0, 1e9] us");
                if (*out.min > *out.max) r.fail("min is above max");
            } else {
                out.max = r.number_in(0, 1e9, "[0, 1e9] us");
            }
        };
        range("max_us", l.max_us);
        range("p99_us", l.p99_us);
        range("mean_us", l.mean_us);
        range("period_max_us", l.period_max_us);
        range("period_p99_us", l.period_p99_us);
        range("period_mean_us", l.period_mean_us);
        if (c.has("include_eeprom_writes")) l.include_eeprom_writes = c.child("include_eeprom_writes").boolean();
        if (!l.max_us.set() && !l.p99_us.set() && !l.mean_us.set() && !l.period_max_us.set() &&
            !l.period_p99_us.set() && !l.period_mean_us.set()) {
            c.fail("give at least one bound (max_us, p99_us, mean_us, period_max_us, period_p99_us, period_mean_us)");
        }
        return l;
    }
    if (kind == "expect-isr") {
        c.keys({"vector", "max_latency_cycles", "max_duration_cycles", "min_count"}, {"vector"});
        ExpectIsr e;
        e.vector = c.child("vector").str();
        const std::vector<const char*>& names = c.board().mcu->vector_names;
        if (e.vector == "RESET" ||
            std::find_if(names.begin(), names.end(), [&](const char* n) { return e.vector == n; }) == names.end()) {
            c.child("vector").fail(fmt::format("'{}' is not an interrupt of the {} (avr-libc's names without _vect: "
                                               "{})",
                                               e.vector, c.board().mcu->label,
                                               fmt::join(names.begin() + 1, names.end(), ", ")));
        }
        if (c.has("max_latency_cycles")) e.max_latency_cycles = c.child("max_latency_cycles").count();
        if (c.has("max_duration_cycles")) e.max_duration_cycles = c.child("max_duration_cycles").count();
        if (c.has("min_count")) e.min_count = c.child("min_count").count();
        return e;
    }
    if (kind == "expect-no-torn-reads") {
        ExpectNoTornReads e;
        if (c.node().IsSequence()) {
            for (std::size_t i = 0; i < c.node().size(); ++i) {
                const YAML::Node v = c.node()[i];
                if (!v.IsScalar() || v.Scalar().empty()) c.fail("expected a list of variable names");
                e.variables.push_back(v.Scalar());
            }
            if (e.variables.empty()) c.fail("expected a list of variable names (or no value: every variable)");
        } else if (!c.node().IsNull() && !(c.node().IsMap() && c.node().size() == 0)) {
            c.fail("takes no value (every variable) or a list of variable names");
        }
        return e;
    }
    return std::nullopt;
}

}  // namespace ddmr::tools::scenario::yaml
