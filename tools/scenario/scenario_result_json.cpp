#include "scenario/scenario_result_json.hpp"

#include "common/sketch_build.hpp"
#include "hil/avr_core.hpp"

namespace ddmr::tools::scenario {

using nlohmann::json;

json scenario_result_json(const Scenario& s, const ScenarioResult& r, const std::vector<std::string>& wiring_warnings) {
    json steps = json::array();
    for (const auto& o : r.steps) {
        steps.push_back({{"line", o.line}, {"kind", o.kind}, {"step", o.text}, {"passed", o.passed},
                         {"cycle", o.cycle}, {"t_s", hil::cycles_to_s(o.cycle, r.clock_hz)}, {"message", o.message}});
    }
    return json{
        {"name", r.name},
        {"file", r.file.string()},
        {"firmware", s.firmware.string()},
        {"sketch", s.sketch_build ? [&] {
             // Built (or found) before the suite ran: whether this worker found it cached says nothing.
             json j = sketch_build_json(*s.sketch_build);
             j.erase("from_cache");
             return j;
         }()
                                   : json(nullptr)},
        {"platformio", s.firmware_source},
        {"seed", s.seed},
        {"baud", s.baud},
        {"verdict", to_string(r.verdict)},
        {"exit_code", exit_code(r.verdict)},
        {"message", r.message},
        {"cycles", r.cycles},
        {"clock_hz", r.clock_hz},
        {"sim_seconds", r.sim_seconds},
        {"steps", steps},
        {"steps_total", s.steps.size()},
        {"uart_bytes", r.uart_bytes},
        {"framing_errors", r.framing_errors},
        {"board", s.board_file ? json(s.board_file->string()) : json(nullptr)},
        {"world", s.world_file ? json(s.world_file->string()) : json(nullptr)},
        {"wiring_warnings", wiring_warnings},
    };
}

}  // namespace ddmr::tools::scenario
