#include "firmware_run_plan.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/firmware_diagnostics.hpp"
#include "common/sha256.hpp"
#include "hil/avr_core.hpp"
#include "hil/board.hpp"
#include "hil/plant_coupler.hpp"
#include "hil/world_file.hpp"
#include "loop_mark.hpp"
#include "plant/params_yaml.hpp"

namespace ddmr::tools {
namespace {

hil::RigConfig rig_config(const FirmwareRunOptions& o) {
    hil::RigConfig c;
    if (o.plant_params) {
        c.plant = *o.plant_params;
    } else if (o.plant_file) {
        c.plant = plant::load_robot_params(*o.plant_file);
    }
    if (o.board_file) {
        c.board = hil::load_board_file(*o.board_file);
        if (o.board_name && *o.board_name != c.board.model) {
            const std::string origin = o.board_name_origin.empty()
                                           ? fmt::format("--board-name {}", hil::board_description(*o.board_name).key)
                                           : o.board_name_origin;
            throw std::invalid_argument(fmt::format("{}: the board file {} is for the {} (board: {}){}", origin,
                                                    c.board.source, hil::board_description(c.board.model).label,
                                                    hil::board_description(c.board.model).key, o.board_name_advice));
        }
    } else if (o.board_name) {
        c.board.model = *o.board_name;  // the thesis robot's wiring on that board
        c.board.source = fmt::format("built-in default board on the {}", hil::board_description(*o.board_name).key);
        hil::validate(c.board);
    }
    if (o.world_file) c.world = hil::load_world_file(*o.world_file);
    c.coupler.mode = o.pwm;
    c.coupler.step_cycles = o.coupling_step_cycles;
    // PlantCoupler checks this too; here the message names the option and the board.
    const hil::BoardDescription& board = hil::board_description(c.board.model);
    const hil::CouplerConfig coupler = hil::resolved(c.coupler, board.clock_hz);
    if (coupler.truth_period_cycles % coupler.step_cycles != 0) {
        throw std::invalid_argument(fmt::format("--coupling-step {} cycles: must divide the {}-cycle (1 ms) truth "
                                                "period of the {} at {} MHz",
                                                coupler.step_cycles, coupler.truth_period_cycles, board.label,
                                                board.clock_hz / 1e6));
    }
    c.eeprom_timing = o.eeprom_timing;
    c.uart_timing = o.uart_timing;
    const std::optional<int> port = hil::parse_serial_port(board, o.serial_port);
    if (!port) {
        throw std::invalid_argument(fmt::format("--serial-port {}: the {} ({}) has {}", o.serial_port, board.label,
                                                board.mcu->label, hil::serial_port_list(board)));
    }
    c.host_usart = *port;
    return c;
}

}  // namespace

/// "name[:type]" -> a traced variable; the type defaults by the symbol's size.
hil::TracedVariable parse_trace_spec(const std::string& spec, const hil::ElfImage& elf) {
    const auto colon = spec.find(':');
    hil::TracedVariable v;
    v.name = spec.substr(0, colon);
    if (v.name.empty()) throw std::invalid_argument("--trace '" + spec + "': empty variable name");
    if (colon != std::string::npos) {
        try {
            v.type = hil::parse_var_type(spec.substr(colon + 1));
        } catch (const std::exception& e) {
            throw std::invalid_argument("--trace '" + spec + "': " + e.what());
        }
        return v;
    }
    const auto sym = elf.find(v.name);
    if (!sym) throw std::invalid_argument("--trace '" + spec + "': firmware has no symbol '" + v.name + "'");
    const auto type = hil::default_var_type(sym->size, hil::FourByteDefault::kFloat);
    if (!type) {
        throw std::invalid_argument("--trace '" + spec + "': '" + v.name + "' has " + std::to_string(sym->size) +
                                    " bytes; give its type as name:type");
    }
    v.type = *type;
    return v;
}

std::optional<std::filesystem::path> reference_contract_for(const std::filesystem::path& firmware) {
    namespace fs = std::filesystem;
    if (fs::exists(firmware) && fs::exists(DDMR_DEFAULT_FIRMWARE) && fs::equivalent(firmware, DDMR_DEFAULT_FIRMWARE)) {
        return fs::path(DDMR_DEFAULT_CONTRACT);
    }
    return std::nullopt;
}

RunPlan plan_firmware_run(const FirmwareRunOptions& options) {
    RunPlan plan;
    std::optional<hil::SketchContract>& contract = plan.contract;
    if (options.contract) contract = hil::load_sketch_contract(*options.contract);
    if (!contract && options.reference_protocol_required) {
        throw std::invalid_argument(fmt::format(
            "--case / --ready-symbol need a sketch contract (run --contract FILE, docs/contracts.md): {} has none",
            options.firmware.string()));
    }
    const bool has_start = plan.has_start = contract && contract->start;
    if (options.case_given && !(has_start && !contract->start->cases.empty())) {
        throw std::invalid_argument(fmt::format("--case {}: the sketch contract {} takes no case", options.test_case,
                                                contract ? contract->source : std::string("(none)")));
    }
    const int test_case = plan.test_case = has_start && !contract->start->cases.empty()
                              ? (options.case_given ? options.test_case : contract->start->default_case)
                              : 0;
    plan.start_text = has_start ? contract->start_text(test_case) : std::string();
    if (!(options.max_wall_seconds > 0.0) || !std::isfinite(options.max_wall_seconds)) {
        throw std::invalid_argument(fmt::format("--wall-timeout {}: must be a positive number of seconds",
                                                options.max_wall_seconds));
    }
    if (!(options.max_sim_seconds > 0.0) || !std::isfinite(options.max_sim_seconds)) {
        throw std::invalid_argument(
            fmt::format("--seconds {}: must be a positive number of simulated seconds",
                        options.max_sim_seconds));
    }
    if (options.vcd) {
        try {
            check_output_file(*options.vcd);
        } catch (const std::exception& e) {
            throw std::invalid_argument("--vcd " + options.vcd->string() + ": " + e.what());
        }
    }
    plan.elf = hil::ElfImage::read(options.firmware);
    const hil::ElfImage& elf = plan.elf;
    plan.config = rig_config(options);  // the board file's errors first
    const hil::BoardDescription& board = hil::board_description(plan.config.board.model);
    plan.board = &board;
    elf.require_mcu(*board.mcu, board.key);
    hil::AvrCore::check_loadable(elf, *board.mcu);
    // Calls to address 0: a sketch built here was reported by its build.
    plan.zero_calls = scan_zero_calls(elf, !options.firmware_source.contains("sketch"));
    // What the contract names must be in the ELF (checked before anything is written).
    std::optional<hil::ElfSymbol>& ready = plan.ready;
    std::string& ready_symbol = plan.ready_symbol;
    if (has_start && (contract->start->after_return || options.ready_symbol_given)) {
        ready_symbol = options.ready_symbol_given ? options.ready_symbol : *contract->start->after_return;
        ready = elf.find(ready_symbol);
        if (!ready || !ready->is_function) {
            throw std::runtime_error(fmt::format("firmware {}: has no function '{}' ({})", options.firmware.string(),
                                                 ready_symbol,
                                                 options.ready_symbol_given ? "--ready-symbol"
                                                                            : "the contract's start.after-return"));
        }
    }
    std::vector<hil::TracedVariable>& traced = plan.traced;
    std::optional<hil::TracedVariable>& loop_marker = plan.loop_marker;
    if (contract && contract->loop.marker) {
        loop_marker = parse_trace_spec(*contract->loop.marker, elf);
        for (const auto& spec : contract->trace) traced.push_back(parse_trace_spec(spec, elf));
        if (std::none_of(traced.begin(), traced.end(), [&](const auto& v) { return v.name == loop_marker->name; })) {
            traced.push_back(*loop_marker);
        }
    }
    if (contract && contract->pose) {
        for (const std::string& name : {contract->pose->x, contract->pose->y, contract->pose->theta}) {
            const auto sym = elf.find(name);
            if (!sym || !sym->is_object || sym->size != 4) {
                throw std::runtime_error(fmt::format("firmware {}: has no 4-byte float global '{}' (the contract {}'s pose)",
                                                     options.firmware.string(), name, contract->source));
            }
        }
    }
    if (contract && contract->eeprom_log) {
        const auto& l = *contract->eeprom_log;
        if (l.max_samples(static_cast<int>(board.mcu->eeprom_bytes)) == 0) {
            throw std::invalid_argument(fmt::format(
                "contract {}: eeprom-log: the series at x-address {} and y-address {} leave no room for a sample "
                "in the {}'s {}-byte EEPROM",
                contract->source, l.x_address, l.y_address, board.mcu->label, board.mcu->eeprom_bytes));
        }
    }
    plan.reports = contract && contract->report == hil::ReportFormat::kDdmrTracking;
    // --unity replaces the contract's `complete` (Unity's summary ends the run).
    plan.contract_completes = !options.unity && contract && contract->complete;
    plan.completes = options.unity || plan.contract_completes;
    std::optional<hil::ElfSymbol>& loop_mark = plan.loop_mark;
    if (options.profile_top == 0) {
        throw std::invalid_argument("--top 0: give the number of functions to print, >= 1");
    }
    const std::string& loop_mark_name = plan.loop_mark_name =
        options.loop_mark_given || !options.profile ? options.loop_mark
        : contract && contract->loop.function       ? *contract->loop.function
                                                    : default_loop_mark(elf);
    if (options.profile) {
        loop_mark = resolve_loop_mark(elf, loop_mark_name,
                                      options.loop_mark_given || !contract || !contract->loop.function
                                          ? "--loop-mark"
                                          : "the contract's loop.function");
    }
    plan.sends = options.sends;
    std::stable_sort(plan.sends.begin(), plan.sends.end(), [](const auto& a, const auto& b) { return a.at_s < b.at_s; });
    if (options.eeprom_preload) plan.preload = hil::EepromPort::load_image(*options.eeprom_preload, *board.mcu);
    // trace.csv: the user's globals, per iteration or every N cycles.
    for (const auto& spec : options.trace) plan.trace_vars.push_back(parse_trace_spec(spec, elf));
    if (!plan.trace_vars.empty() && options.trace_every_cycles == 0 && !loop_marker) {
        throw std::invalid_argument("--trace without --trace-every samples once per loop iteration, which needs "
                                    "the sketch contract's loop.marker: give --trace-every N (cycles)");
    }
    plan.sha256 = sha256_file_hex(options.firmware);
    return plan;

}

}  // namespace ddmr::tools
