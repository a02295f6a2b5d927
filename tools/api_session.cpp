#include "api_session.hpp"
#include "api_session_live.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <system_error>
#include <utility>

#include "common/plant_yaml.hpp"
#include "common/private_dir.hpp"
#include "common/sketch_build.hpp"
#include "common/truth_csv.hpp"
#include "firmware_run_plan.hpp"
#include "hil/board.hpp"
#include "hil/board_description.hpp"
#include "plant/params_yaml.hpp"
#include "scenario/step_failed.hpp"

namespace ddmr::tools {
namespace {

namespace fs = std::filesystem;
using hil::Cycles;

/// The sketch's build for the board the board file names (else the Uno).
SketchBuildOptions sketch_options(const ApiOptions& o) {
    SketchBuildOptions b;
    b.fqbn = hil::board_description(o.board_file ? hil::load_board_file(*o.board_file).model : hil::BoardModel::uno).fqbn;
    b.libraries = o.libraries;
    b.more_libraries_advice = "pass libraries=[DIR]";
    return b;
}

uint64_t next_session_id() {
    static std::atomic<uint64_t> next{1};
    return next++;
}

/// The plant: its file or the defaults, the overrides merged in, the seed.
plant::RobotParams resolve_plant(const ApiOptions& o, std::string& source) {
    if (o.plant_file) plant::load_robot_params(*o.plant_file);  // its own messages name its file and line
    YAML::Node yaml = o.plant_file ? YAML::LoadFile(o.plant_file->string()) : default_plant_yaml();
    source = o.plant_file ? o.plant_file->string() : std::string("(embedded defaults)");
    for (const std::string& layer : o.plant_overrides) {
        YAML::Node over;
        try {
            over = YAML::Load(layer);
        } catch (const YAML::Exception& e) {
            throw std::invalid_argument(fmt::format("plant overrides: not YAML or JSON: {}", e.msg));
        }
        if (!over.IsMap()) {
            throw std::invalid_argument("plant overrides: expected a mapping like {motor1: {resistance_ohm: 6.0}}");
        }
        merge_plant_yaml(yaml, over);  // as a scenario's overrides: a layer's encoder resolution replaces the other's
    }
    if (!o.plant_overrides.empty()) source += " + overrides";
    if (o.seed) seed_plant_yaml(yaml, *o.seed);
    YAML::Emitter e;
    e << yaml;
    return plant::parse_robot_params(e.c_str(), o.plant_overrides.empty() ? source : "plant overrides");
}

FirmwareRunOptions run_options(const ApiOptions& o, const nlohmann::json& firmware_source, const fs::path& staging) {
    FirmwareRunOptions fo;
    fo.firmware = o.firmware;
    fo.firmware_source = firmware_source;
    if (o.contract) {
        fo.contract = *o.contract;
    } else {
        fo.contract = reference_contract_for(o.firmware);  // as `run` takes it
    }
    fo.max_sim_seconds = o.max_sim_seconds;
    fo.max_wall_seconds = 1e9;  // a Python test runs as long as it likes (Ctrl-C stops it)
    fo.out_dir = staging;
    fo.baud = o.baud;
    fo.board_file = o.board_file;
    fo.world_file = o.world_file;
    fo.plant_file = o.plant_file;
    if (!o.plant_overrides.empty() || o.seed) {
        std::string source;
        fo.plant_params = resolve_plant(o, source);
        fo.plant_source = source;
    }
    fo.instruments = o.instruments;
    fo.profile = o.profile;
    fo.fast_forward = o.fast_forward;
    if (!o.loop_mark.empty()) {
        fo.loop_mark = o.loop_mark;
        fo.loop_mark_given = true;
    }
    fo.contract_drives = false;  // run_contract() hands the run to the contract
    return fo;
}

}  // namespace

ApiSession::Live::Live(const ApiOptions& options, const nlohmann::json& firmware_source) : staging(make_private_dir("ddmr-hil-session")) {
    try {
        run = std::make_unique<FirmwareRun>(run_options(options, firmware_source, staging));
    } catch (...) {
        std::error_code ignored;
        fs::remove_all(staging, ignored);
        throw;
    }
    hil::Session& session = run->session();
    observer = std::make_unique<Observer>(session, truth_rows);
    session.attach(*observer);
    faults = std::make_unique<scenario::FaultSteps>(session);
    std::string header = truth_csv_header(/*with_drive=*/true);
    header.pop_back();
    for (std::size_t at = 0;;) {
        const std::size_t comma = header.find(',', at);
        truth_columns.push_back(header.substr(at, comma - at));
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    for (const std::string& c : session.rig().extra_truth_columns()) truth_columns.push_back(c);
}

ApiSession::Live::~Live() {
    waveforms.clear();  // what watches the core goes before it
    driver.reset();
    faults.reset();
    run.reset();  // its writers' temporary files too
    std::error_code ignored;
    fs::remove_all(staging, ignored);
}

ApiSession::ApiSession(const ApiOptions& options) : options_(options), id_(next_session_id()) {
    if (!options_.sketch && options_.firmware.empty()) {
        throw std::invalid_argument("Session: give firmware (an ELF built for the board's MCU) or sketch (an .ino to build)");
    }
    if (options_.sketch) {
        if (!options_.firmware.empty()) {
            throw std::invalid_argument("Session: give firmware (an ELF) or sketch (an .ino to build), not both");
        }
        const SketchBuild built = build_sketch(sketch_ino(*options_.sketch, "sketch"), sketch_options(options_));
        options_.firmware = built.elf;
        firmware_source_ = sketch_build_json(built);
    }
    live_ = start();
}

ApiSession::~ApiSession() = default;

std::unique_ptr<ApiSession::Live> ApiSession::start() const { return std::make_unique<Live>(options_, firmware_source_); }

FirmwareRun& ApiSession::run() { return *live_->run; }
const std::vector<std::string>& ApiSession::truth_columns() const { return live_->truth_columns; }
const std::vector<double>& ApiSession::truth_rows() const { return live_->truth_rows; }
const std::string& ApiSession::exit_reason() const { return live_->exit_reason; }

Cycles ApiSession::cycle() { return run().session().cycle(); }
double ApiSession::time_s() { return run().session().seconds(cycle()); }

void ApiSession::check_running() const {
    if (!live_->ended.empty()) throw ApiRunEnded(live_->ended);
}

void ApiSession::end_run(hil::SessionStop stop) {
    live_->last_stop = stop;
    hil::Session& session = run().session();
    switch (stop) {
        case hil::SessionStop::kFailure:
        case hil::SessionStop::kWallLimit:
        case hil::SessionStop::kKilled: live_->ended = session.end_message(stop); break;
        case hil::SessionStop::kEnded: live_->ended = "the run was ended"; break;
        case hil::SessionStop::kTimeLimit:
            live_->ended = fmt::format("the session's time limit ({} s of AVR time) was reached", run().options().max_sim_seconds);
            break;
        default: return;
    }
    throw ApiRunEnded(live_->ended);
}

void ApiSession::run_to(Cycles target, const std::function<bool()>& stop_when, const Between& between) {
    check_running();
    hil::Session& session = run().session();
    const Cycles chunk = hil::s_to_cycles(kChunkSeconds, session.core().clock_hz());
    hil::RunCondition until;
    if (stop_when) until.met = stop_when;
    while (session.cycle() < target) {
        const hil::SessionStop stop = session.run(std::min(target, session.cycle() + chunk), until);
        live_->last_stop = stop;
        if (stop != hil::SessionStop::kReachedCycle && stop != hil::SessionStop::kCondition) end_run(stop);
        if (stop_when && stop_when()) return;
        if (between) between();
    }
}

void ApiSession::run_for(double seconds, const Between& between) {
    if (!(seconds >= 0.0) || !std::isfinite(seconds)) {
        throw std::invalid_argument(fmt::format("run_for({}): the AVR time must be a number of seconds >= 0", seconds));
    }
    run_to(cycle() + hil::s_to_cycles(seconds, run().session().core().clock_hz()), {}, between);
}

void ApiSession::run_until_serial(const std::string& text, double timeout_s, const Between& between) {
    if (text.empty()) throw std::invalid_argument("run_until_serial: the text is empty");
    if (!(timeout_s > 0.0) || !std::isfinite(timeout_s)) {
        throw std::invalid_argument(fmt::format("run_until_serial: timeout_s {} must be a positive number", timeout_s));
    }
    live_->observer->await(text);
    const double from = time_s();
    run_to(cycle() + hil::s_to_cycles(timeout_s, run().session().core().clock_hz()),
           [this] { return live_->observer->seen(); }, between);
    if (!live_->observer->seen()) {
        throw ApiTimeout(fmt::format("'{}' did not come within {} s of AVR time (from t = {:.3f} s to {:.3f} s)",
                                     scenario::printable(text), timeout_s, from, time_s()));
    }
}

void ApiSession::run_until(const std::function<bool()>& condition, double timeout_s, const Between& between) {
    if (!(timeout_s > 0.0) || !std::isfinite(timeout_s)) {
        throw std::invalid_argument(fmt::format("run_until: timeout_s {} must be a positive number", timeout_s));
    }
    if (condition()) return;
    const uint32_t clock_hz = run().session().core().clock_hz();
    const Cycles end = cycle() + hil::s_to_cycles(timeout_s, clock_hz);
    const Cycles ms = hil::s_to_cycles(1e-3, clock_hz);
    const double from = time_s();
    bool held = false;
    while (!held && cycle() < end) {
        run_to(std::min(end, cycle() + ms), {}, {});
        held = condition();
        if (between && !held) between();
    }
    if (!held) {
        throw ApiTimeout(fmt::format("the condition did not hold within {} s of AVR time (from t = {:.3f} s to {:.3f} s)",
                                     timeout_s, from, time_s()));
    }
}

std::string ApiSession::run_contract(std::optional<int> test_case, const Between& between) {
    check_running();
    if (cycle() != 0) {
        throw std::logic_error("run_contract() runs the sketch contract from reset: call it on a fresh Session");
    }
    if (!run().plan().contract) {
        throw std::invalid_argument(fmt::format("run_contract: {} has no sketch contract (Session(contract=FILE), "
                                                "docs/contracts.md)",
                                                run().options().firmware.string()));
    }
    if (test_case) run().set_case(*test_case);
    hil::SessionStop stop{};
    try {
        stop = run().run_to_end(between);
    } catch (...) {
        live_->ended = "run_contract() was stopped before the contract's end: the session cannot run on (restore a "
                       "snapshot, or start a new Session)";
        throw;
    }
    live_->last_stop = stop;
    const FirmwareRunResult r = run().finish(stop);
    live_->exit_reason = to_string(r.exit);
    live_->ended = fmt::format("the contract's run has ended ({}): the session cannot run on", live_->exit_reason);
    return live_->exit_reason;
}

const std::string& ApiSession::serial_text() const { return live_->observer->text(); }

std::string ApiSession::serial_read_new() {
    const std::string& t = live_->observer->text();
    std::string out = t.substr(std::min(live_->read_mark, t.size()));
    live_->read_mark = t.size();
    return out;
}

int ApiSession::pin_number(const std::string& name) {
    const hil::BoardDescription& board = run().session().core().board();
    const std::optional<int> pin = hil::parse_pin_name(board, name);
    if (!pin) {
        throw std::invalid_argument(
            fmt::format("pin '{}': the {} has pins {}", name, board.label, hil::pin_range(board)));
    }
    return *pin;
}

bool ApiSession::pin_level(int pin) {
    hil::AvrCore& core = run().session().core();
    const hil::PinInfo info = *hil::board_pin(core.board(), pin);
    auto& w = live_->waveforms[pin];
    if (!w) w = std::make_unique<hil::PinWaveforms>(core, std::vector<int>{pin});
    w->advance_to(core.cycle());
    if (w->mode(pin) == hil::PinMode::output) return w->level_at(pin, core.cycle());
    return ((core.data(info.pin_register) >> info.bit) & 1U) != 0;
}

double ApiSession::pwm_duty(int pin) {
    (void)pin_level(pin);  // builds and advances its waveform
    const hil::PinWaveforms& w = *live_->waveforms[pin];
    return w.mode(pin) == hil::PinMode::output ? w.duty(pin) : 0.0;
}

plant::Pose ApiSession::pose() { return run().session().rig().robot().pose(); }

std::vector<uint8_t> ApiSession::eeprom() {
    const hil::EepromImage image = run().session().rig().eeprom().read_all();
    return {image.begin(), image.end()};
}

std::vector<std::string> ApiSession::warnings() { return run().session().rig().warnings(); }

void ApiSession::save_artifacts(const fs::path& dir) {
    if (!run().finished()) {
        const FirmwareRunResult r = run().finish(live_->last_stop);
        live_->exit_reason = to_string(r.exit);
        if (live_->ended.empty()) live_->ended = "the session's artifacts were saved: it cannot run on (start a new Session)";
    }
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (ec) throw std::runtime_error(fmt::format("save_artifacts: cannot create {}: {}", dir.string(), ec.message()));
    for (const auto& e : fs::directory_iterator(live_->staging)) {
        if (!e.is_regular_file()) continue;
        // Each file whole or not at all: copied beside its place, then renamed.
        const fs::path partial = dir / ("." + e.path().filename().string() + ".partial");
        fs::copy_file(e.path(), partial, fs::copy_options::overwrite_existing, ec);
        if (!ec) fs::rename(partial, dir / e.path().filename(), ec);
        if (ec) {
            throw std::runtime_error(
                fmt::format("save_artifacts: cannot write {}: {}", (dir / e.path().filename()).string(), ec.message()));
        }
    }
}

}  // namespace ddmr::tools
