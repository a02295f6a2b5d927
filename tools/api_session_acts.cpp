// ApiSession's acts on the robot (serial bytes, faults, pin drives, global
// writes, held sensor readings, the loop profile's start), each logged with
// its cycle, and the snapshots that replay that log (api_session.hpp).

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <type_traits>
#include <utility>
#include <variant>

#include "api_session.hpp"
#include "api_session_live.hpp"
#include "firmware_run_plan.hpp"
#include "hil/board.hpp"
#include "hil/board_description.hpp"
#include "run_outputs.hpp"
#include "scenario/step_parsers.hpp"

namespace ddmr::tools {
namespace {

using hil::Cycles;

/// Whether FaultSteps runs step action A (parse_fault_step returns only those).
template <typename A, typename = void>
struct IsFault : std::false_type {};
template <typename A>
struct IsFault<A, std::void_t<decltype(std::declval<scenario::FaultSteps&>().run(std::declval<const A&>()))>>
    : std::true_type {};

constexpr const char* kNotAFault = "fault '{}': not a fault (inject, stall, battery, slip, place, push, move-obstacle)";

/// A scenario fault step, checked as a scenario's, run now.
void run_fault(hil::Session& session, scenario::FaultSteps& faults, const ApiAction::Fault& f) {
    YAML::Node node;
    try {
        node = YAML::Load(f.value);
    } catch (const YAML::Exception& e) {
        throw std::invalid_argument(fmt::format("fault {}: not YAML or JSON: {}", f.kind, e.msg));
    }
    const scenario::yaml::Ctx c("fault()", node, f.kind, session.core().board(), &session.rig().config().board);
    const std::optional<scenario::StepAction> action = scenario::yaml::parse_fault_step(f.kind, c);
    if (!action) throw std::invalid_argument(fmt::format(kNotAFault, f.kind));
    if (const auto* m = std::get_if<scenario::MoveObstacle>(&*action)) {
        if (!plant::find_obstacle(session.rig().world(), m->name)) {
            throw std::invalid_argument(fmt::format("move-obstacle: the world has no obstacle named '{}'", m->name));
        }
    }
    const bool ran = std::visit(
        [&faults](const auto& a) {
            using A = std::decay_t<decltype(a)>;
            if constexpr (IsFault<A>::value) {
                (void)faults.run(a);
                return true;
            } else {
                return false;  // parse_fault_step also reads `reset`, a scenario step, not a fault
            }
        },
        *action);
    if (!ran) throw std::invalid_argument(fmt::format(kNotAFault, f.kind));
}

/// Throws for a pin the board wires or the host's serial port uses: a
/// second source on it would fight the part (or the adapter) driving it.
void check_free_pin(hil::Session& session, int pin) {
    const hil::BoardDescription& board = session.core().board();
    const std::map<int, std::string> uses = hil::pin_uses(session.rig().config().board);
    if (const auto it = uses.find(pin); it != uses.end()) {
        throw std::invalid_argument(fmt::format("pin {}: the board wires it ({}); drive a free input pin, or set the "
                                                "part's reading (sensor(NAME).set)",
                                                pin, it->second));
    }
    const int usart = session.rig().config().host_usart.value_or(board.console_usart);
    const hil::UsartDesc& u = board.mcu->usarts.at(static_cast<std::size_t>(usart));
    if (hil::pin_number_of(board, u.rxd) == pin || hil::pin_number_of(board, u.txd) == pin) {
        throw std::invalid_argument(
            fmt::format("pin {} carries {}, the host's serial port", pin, hil::serial_port_name(usart)));
    }
}

hil::Variable resolve_var(hil::Session& session, const std::string& name, const std::string& type) {
    const hil::TracedVariable v = parse_trace_spec(type.empty() ? name : name + ":" + type, session.elf());
    return session.rig().variables().lookup(v.name, v.type);
}

}  // namespace

void ApiSession::act(ApiAction::Act action) {
    check_running();
    apply(action);  // throws, logging nothing, for a bad act
    live_->log.push_back(ApiAction{cycle(), std::move(action)});
}

void ApiSession::apply(const ApiAction::Act& action) {
    Live& live = *live_;
    hil::Session& session = live.run->session();
    std::visit(
        [&](const auto& a) {
            using A = std::decay_t<decltype(a)>;
            if constexpr (std::is_same_v<A, ApiAction::SerialWrite>) {
                session.send(a.bytes);
            } else if constexpr (std::is_same_v<A, ApiAction::Fault>) {
                run_fault(session, *live.faults, a);
            } else if constexpr (std::is_same_v<A, ApiAction::PinDrive>) {
                check_free_pin(session, a.pin);
                if (!live.driver) live.driver = std::make_unique<hil::PinDriver>(session.core());
                live.driver->drive_now(a.pin, a.level);
            } else if constexpr (std::is_same_v<A, ApiAction::VarWrite>) {
                const hil::Variable v = resolve_var(session, a.name, a.type);
                const std::array<uint8_t, 4> bytes = hil::encode_var(v.type, a.value);
                for (std::size_t i = 0; i < v.size; ++i) {
                    session.core().set_sram(static_cast<uint16_t>(v.address + i), bytes[i]);
                }
            } else if constexpr (std::is_same_v<A, ApiAction::SensorSet>) {
                session.rig().parts().set_reading(a.part, a.reading, a.value);
            } else {
                hil::LoopProfiler* profiler = live.run->loop_profiler();
                if (profiler == nullptr) {
                    throw std::logic_error("loop_profile: the session has no loop profiler (Session(profile=True))");
                }
                profiler->arm();
            }
        },
        action);
}

double ApiSession::var_read(const std::string& name, const std::string& type) {
    hil::Session& session = run().session();
    return session.rig().variables().read(resolve_var(session, name, type));
}

void ApiSession::fault(const std::string& kind, const std::string& value) { act(ApiAction::Fault{kind, value}); }
void ApiSession::serial_write(const std::string& bytes) { act(ApiAction::SerialWrite{bytes}); }
void ApiSession::pin_drive(int pin, bool level) { act(ApiAction::PinDrive{pin, level}); }

void ApiSession::var_write(const std::string& name, const std::string& type, double value) {
    try {
        act(ApiAction::VarWrite{name, type, value});
    } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(fmt::format("var '{}': {}", name, e.what()));
    }
}

void ApiSession::sensor_set(const std::string& part, const std::string& reading, std::optional<double> value) {
    act(ApiAction::SensorSet{part, reading, value});
}

void ApiSession::loop_profile_start() { act(ApiAction::LoopProfileStart{}); }

const std::vector<hil::LoopIteration>& ApiSession::loop_profile() {
    hil::LoopProfiler* profiler = run().loop_profiler();
    if (profiler == nullptr) throw std::logic_error("loop_profile: the session has no loop profiler (Session(profile=True))");
    tag_eeprom_writes(*profiler, run().session().rig());
    return profiler->iterations();
}

std::string ApiSession::isr_stats_json() {
    const IsrOutputs out = isr_outputs(run().session());
    if (out.isr.is_null()) throw std::logic_error("isr_stats: the ISR monitor is off (Session(instruments=False))");
    return out.isr.dump();
}

ApiSnapshot ApiSession::snapshot() {
    check_running();
    return ApiSnapshot{id_, cycle(), live_->log, live_->read_mark};
}

void ApiSession::restore(const ApiSnapshot& snap, const Between& between) {
    if (snap.session != id_) throw std::logic_error("restore: the snapshot was taken by another Session");
    std::unique_ptr<Live> before = std::exchange(live_, start());
    try {
        // The engine stops at the first instruction boundary at or after a
        // target, and every logged cycle is one: the replay lands on each.
        const auto reach = [&](Cycles at) {
            run_to(at, {}, between);
            if (cycle() != at) {
                throw std::logic_error(fmt::format("restore: the replay reached cycle {}, not the snapshot's {}; "
                                                   "the run is not deterministic (a bug: please report it)",
                                                   cycle(), at));
            }
        };
        for (const ApiAction& a : snap.log) {
            reach(a.at);
            act(a.act);
        }
        reach(snap.cycle);
    } catch (...) {
        live_ = std::move(before);  // as it was: a replay stopped by Ctrl-C changes nothing
        throw;
    }
    live_->read_mark = snap.read_mark;
}

}  // namespace ddmr::tools
