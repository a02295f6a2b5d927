// _ddmr_hil: the pybind11 binding of ApiSession (tools/api_session.hpp),
// the C++ half of the Python package ddmr_hil (tools/python/ddmr_hil,
// docs/python.md). It only converts: every behaviour is ApiSession's.
//
// The GIL is released while the AVR runs; between chunks of AVR time the
// binding takes it back and checks for signals, so Ctrl-C stops a long run
// (KeyboardInterrupt) with the session still usable. C++ errors become the
// package's exceptions with the same one-line messages as the CLI:
//   ApiTimeout -> Timeout, ApiRunEnded -> RunEnded, std::invalid_argument and
//   std::runtime_error (bad input) -> ConfigError (also a ValueError),
//   std::logic_error (a call out of order) -> UsageError (also a RuntimeError).

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cstring>
#include <exception>
#include <stdexcept>

#include "api_session.hpp"

namespace py = pybind11;
using ddmr::tools::ApiOptions;
using ddmr::tools::ApiSession;

namespace {

/// Raises `type` with `what` (bytes that are not UTF-8 replaced, never a decode error instead).
void raise(const py::exception<void>& type, const char* what) {
    py::object text = py::reinterpret_steal<py::object>(
        PyUnicode_DecodeUTF8(what, static_cast<py::ssize_t>(std::strlen(what)), "replace"));
    PyErr_SetObject(type.ptr(), text.ptr());
}

/// Between chunks: Ctrl-C (or any pending signal handler's exception) stops the run.
void check_signals() {
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
}

ApiOptions make_options(const py::dict& kw) {
    ApiOptions o;
    const auto path = [&](const char* key) -> std::optional<std::filesystem::path> {
        if (!kw.contains(key) || kw[key].is_none()) return std::nullopt;
        return std::filesystem::path(py::str(kw[key]).cast<std::string>());
    };
    o.firmware = path("firmware").value_or(std::filesystem::path());
    o.sketch = path("sketch");
    if (kw.contains("libraries") && !kw["libraries"].is_none()) {
        for (const auto& d : kw["libraries"]) o.libraries.emplace_back(py::str(d).cast<std::string>());
    }
    o.board_file = path("board");
    o.plant_file = path("plant_file");
    o.world_file = path("world");
    o.contract = path("contract");
    if (kw.contains("plant_overrides")) o.plant_overrides = kw["plant_overrides"].cast<std::vector<std::string>>();
    if (kw.contains("seed") && !kw["seed"].is_none()) o.seed = kw["seed"].cast<uint64_t>();
    if (kw.contains("max_sim_s")) o.max_sim_seconds = kw["max_sim_s"].cast<double>();
    if (kw.contains("baud") && !kw["baud"].is_none()) o.baud = kw["baud"].cast<uint32_t>();
    if (kw.contains("profile")) o.profile = kw["profile"].cast<bool>();
    if (kw.contains("fast_forward")) o.fast_forward = kw["fast_forward"].cast<bool>();
    if (kw.contains("loop_mark") && !kw["loop_mark"].is_none()) o.loop_mark = kw["loop_mark"].cast<std::string>();
    if (kw.contains("instruments")) {
        const bool on = kw["instruments"].cast<bool>();
        o.instruments = {on, on, on};
    }
    return o;
}

py::array_t<double> history(const ApiSession& s) {
    const std::size_t cols = s.truth_columns().size();
    const std::vector<double>& v = s.truth_rows();
    py::array_t<double> a({static_cast<py::ssize_t>(v.size() / cols), static_cast<py::ssize_t>(cols)});
    std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(double));
    return a;
}

/// The loop profile's iterations as rows: start, mark_entry, end, compute,
/// wait, period [cycles], eeprom_write (0 or 1).
py::array_t<uint64_t> loop_rows(ApiSession& s) {
    const std::vector<ddmr::hil::LoopIteration>& it = s.loop_profile();
    py::array_t<uint64_t> a({static_cast<py::ssize_t>(it.size()), static_cast<py::ssize_t>(7)});
    auto r = a.mutable_unchecked<2>();
    for (std::size_t i = 0; i < it.size(); ++i) {
        const auto k = static_cast<py::ssize_t>(i);
        const ddmr::hil::LoopIteration& x = it[i];
        r(k, 0) = x.start;
        r(k, 1) = x.mark_entry;
        r(k, 2) = x.end;
        r(k, 3) = x.compute();
        r(k, 4) = x.wait();
        r(k, 5) = x.period();
        r(k, 6) = x.eeprom_write ? 1U : 0U;
    }
    return a;
}

}  // namespace

PYBIND11_MODULE(_ddmr_hil, m) {
    m.doc() = "ddmr-hil's engine (use the ddmr_hil package, not this module)";
    static py::exception<void> base(m, "DdmrHilError");
    static py::exception<void> timeout(m, "Timeout", base);
    static py::exception<void> run_ended(m, "RunEnded", base);
    static py::exception<void> config(m, "ConfigError", py::make_tuple(base, py::handle(PyExc_ValueError)));
    static py::exception<void> usage(m, "UsageError", py::make_tuple(base, py::handle(PyExc_RuntimeError)));
    // pybind11 takes a void (*)(std::exception_ptr): the parameter must be by value.
    py::register_exception_translator([](std::exception_ptr p) {  // NOLINT(performance-unnecessary-value-param)
        try {
            if (p) std::rethrow_exception(p);
        } catch (const py::cast_error&) {
            throw;  // pybind11's own TypeError
        } catch (const ddmr::tools::ApiTimeout& e) {
            raise(timeout, e.what());
        } catch (const ddmr::tools::ApiRunEnded& e) {
            raise(run_ended, e.what());
        } catch (const std::invalid_argument& e) {
            raise(config, e.what());
        } catch (const std::logic_error& e) {
            raise(usage, e.what());
        } catch (const std::runtime_error& e) {
            raise(config, e.what());
        }
    });

    py::class_<ddmr::tools::ApiSnapshot>(m, "_Snapshot")
        .def_readonly("cycle", &ddmr::tools::ApiSnapshot::cycle)
        .def_property_readonly("acts", [](const ddmr::tools::ApiSnapshot& s) { return s.log.size(); });

    py::class_<ApiSession>(m, "_Session")
        .def(py::init([](const py::dict& kw) { return std::make_unique<ApiSession>(make_options(kw)); }))
        .def_property_readonly("cycle", &ApiSession::cycle)
        .def_property_readonly("time_s", &ApiSession::time_s)
        .def("run_for", [](ApiSession& s, double seconds) {
            py::gil_scoped_release free;
            s.run_for(seconds, check_signals);
        })
        .def("run_until_serial", [](ApiSession& s, const std::string& text, double timeout_s) {
            py::gil_scoped_release free;
            s.run_until_serial(text, timeout_s, check_signals);
        })
        .def("run_until", [](ApiSession& s, const py::function& condition, double timeout_s) {
            py::gil_scoped_release free;
            s.run_until(
                [&condition] {
                    py::gil_scoped_acquire gil;
                    return condition().cast<bool>();
                },
                timeout_s, check_signals);
        })
        .def("run_contract", [](ApiSession& s, std::optional<int> test_case) {
            py::gil_scoped_release free;
            return s.run_contract(test_case, check_signals);
        })
        .def("fault", &ApiSession::fault)
        .def("serial_write", [](ApiSession& s, const py::bytes& b) { s.serial_write(b.cast<std::string>()); })
        .def("serial_text", [](const ApiSession& s) { return py::bytes(s.serial_text()); })
        .def("serial_read_new", [](ApiSession& s) { return py::bytes(s.serial_read_new()); })
        .def("pin_drive", &ApiSession::pin_drive)
        .def("var_write", &ApiSession::var_write)
        .def("sensor_set", &ApiSession::sensor_set)
        .def("isr_stats_json", &ApiSession::isr_stats_json)
        .def("loop_profile_start", &ApiSession::loop_profile_start)
        .def("loop_profile", &loop_rows)
        .def("snapshot", &ApiSession::snapshot)
        .def("restore", [](ApiSession& s, const ddmr::tools::ApiSnapshot& snap) {
            py::gil_scoped_release free;
            s.restore(snap, check_signals);
        })
        .def("pin_number", &ApiSession::pin_number)
        .def("pin_level", &ApiSession::pin_level)
        .def("pwm_duty", &ApiSession::pwm_duty)
        .def("var_read", &ApiSession::var_read)
        .def("pose", [](ApiSession& s) {
            const auto p = s.pose();
            return py::make_tuple(p.x_m, p.y_m, p.theta_rad);
        })
        .def("truth_columns", &ApiSession::truth_columns)
        .def("truth_history", &history)
        .def("eeprom", [](ApiSession& s) {
            const std::vector<uint8_t> e = s.eeprom();
            return py::bytes(reinterpret_cast<const char*>(e.data()), e.size());
        })
        .def("warnings", &ApiSession::warnings)
        .def("save_artifacts", &ApiSession::save_artifacts)
        .def_property_readonly("exit_reason", &ApiSession::exit_reason);
}
