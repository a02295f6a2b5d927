#include "firmware_run.hpp"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "common/atomic_file.hpp"
#include "common/sha256.hpp"
#include "hil/elf_image.hpp"

namespace ddmr::tools {
namespace {

using hil::Cycles;
using nlohmann::json;

/// How often progress is reported and the parser's completion is checked [s].
constexpr double kProgressPeriodS = 1.0;

json number_or_null(const std::optional<double>& v) {
    if (!v || !std::isfinite(*v)) return nullptr;
    return *v;
}

json report_json(const hil::FirmwareReport& r) {
    json pairs = json::array();
    for (const auto& [x, y] : r.eeprom_pairs) pairs.push_back({x, y});
    return json{
        {"banner", r.banner}, {"ended", r.ended},
        {"count1", number_or_null(r.count1)}, {"count2", number_or_null(r.count2)},
        {"gx", number_or_null(r.gx)}, {"gy", number_or_null(r.gy)}, {"t", number_or_null(r.t)},
        {"pdt1", number_or_null(r.pdt1)}, {"pdt2", number_or_null(r.pdt2)},
        {"v", number_or_null(r.v)}, {"w", number_or_null(r.w)},
        {"ex", number_or_null(r.ex)}, {"ey", number_or_null(r.ey)},
        {"theta", number_or_null(r.theta)},
        {"errx", number_or_null(r.errx)}, {"erry", number_or_null(r.erry)},
        {"errxr", number_or_null(r.errxr)},
        {"addr", number_or_null(r.addr)},
        {"eeprom_pairs", pairs},
    };
}

}  // namespace

const char* to_string(RunExit exit) {
    switch (exit) {
        case RunExit::kReportComplete: return "report_complete";
        case RunExit::kTimeout: return "timeout";
        case RunExit::kCrashed: return "crashed";
        case RunExit::kSleepForever: return "sleep_with_interrupts_off";
        case RunExit::kReportMalformed: return "report_malformed";
    }
    return "unknown";
}

FirmwareRunResult run_firmware(const FirmwareRunOptions& options) {
    // --- Validate everything before the output folder is touched. ---
    if (options.test_case != 1 && options.test_case != 2) {
        throw std::invalid_argument(fmt::format("--case {}: the reference sketch knows cases 1 and 2",
                                                options.test_case));
    }
    if (!(options.max_sim_seconds > 0.0) || !std::isfinite(options.max_sim_seconds)) {
        throw std::invalid_argument(
            fmt::format("--seconds {}: must be a positive number of simulated seconds",
                        options.max_sim_seconds));
    }
    const hil::ElfImage elf = hil::ElfImage::read(options.firmware);
    elf.require_atmega328p();
    const hil::ElfSymbol ready = elf.require(options.ready_symbol);
    if (!ready.is_function) {
        throw std::runtime_error(fmt::format("firmware {}: symbol '{}' is not a function",
                                             options.firmware.string(), options.ready_symbol));
    }
    std::optional<hil::EepromImage> preload;
    if (options.eeprom_preload) preload = hil::EepromPort::load_image(*options.eeprom_preload);
    const std::string sha256 = sha256_file_hex(options.firmware);
    prepare_output_dir(options.out_dir);

    // --- Wire the parts and run. ---
    const auto wall_start = std::chrono::steady_clock::now();
    hil::AvrCore core(elf);
    core.log().set_echo(options.echo_simavr_log ? stderr : nullptr);
    hil::UartLink uart(core, options.uart_timing);
    hil::EepromPort eeprom(core);
    if (preload) eeprom.preload(*preload);

    hil::FirmwareReportParser parser(/*expects_eeprom_dump=*/options.test_case == 1);
    uart.set_listener([&](const hil::UartByte& b) {
        const bool was_done = parser.complete() || parser.error().has_value();
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (was_done) return;
        if (parser.error()) {
            core.request_stop();
        } else if (parser.complete()) {
            // The report is sent when its last byte has left the wire.
            core.stop_after(uart.cycles_per_byte());
        }
    });

    FirmwareRunResult result;
    const Cycles limit = hil::s_to_cycles(options.max_sim_seconds, core.clock_hz());
    const auto progress = [&](const char* phase) {
        if (!options.progress) return;
        std::fprintf(stderr, "ddmr-hil run: %-8s t = %6.2f s of %.0f s simulated, %zu UART bytes\n",
                     phase, core.seconds(), options.max_sim_seconds, uart.received().size());
    };

    hil::RunStop stop = core.run_until_return_from(ready, limit);
    if (stop == hil::RunStop::kCondition) {
        result.ready_cycle = core.cycle();
        progress("ready");
        uart.send(std::string(1, static_cast<char>('0' + options.test_case)));
        stop = hil::RunStop::kReachedCycle;
        while (stop == hil::RunStop::kReachedCycle && core.cycle() < limit) {
            const Cycles next = std::min<Cycles>(
                limit, core.cycle() + hil::s_to_cycles(kProgressPeriodS, core.clock_hz()));
            stop = core.run_until(next);
            if (stop == hil::RunStop::kReachedCycle) progress("running");
        }
    }

    result.cycles_total = core.cycle();
    result.wall_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    result.uart_text = uart.text();
    result.eeprom = eeprom.read_all();
    result.report = parser.report();
    const double sim_s = hil::cycles_to_s(result.cycles_total, core.clock_hz());
    switch (stop) {
        case hil::RunStop::kCondition:
            if (parser.error()) {
                result.exit = RunExit::kReportMalformed;
                result.message = *parser.error();
            } else {
                result.exit = RunExit::kReportComplete;
            }
            break;
        case hil::RunStop::kCrashed:
            result.exit = RunExit::kCrashed;
            result.message = fmt::format("firmware crashed at PC 0x{:04x}, cycle {} (t = {:.6f} s)",
                                         core.pc(), core.cycle(), sim_s);
            break;
        case hil::RunStop::kDone:
            result.exit = RunExit::kSleepForever;
            result.message = fmt::format(
                "firmware went to sleep with interrupts off at PC 0x{:04x}, cycle {}", core.pc(),
                core.cycle());
            break;
        case hil::RunStop::kReachedCycle:
            result.exit = RunExit::kTimeout;
            result.message =
                result.ready_cycle
                    ? fmt::format("timeout after {} simulated s: the firmware's report was not "
                                  "complete (raise --seconds?)",
                                  options.max_sim_seconds)
                    : fmt::format("timeout after {} simulated s: the firmware never returned from "
                                  "'{}', so the case byte was never sent",
                                  options.max_sim_seconds, options.ready_symbol);
            break;
    }

    // --- Artifacts, each written atomically. ---
    const double mcycles_per_s =
        result.wall_seconds > 0 ? static_cast<double>(result.cycles_total) / result.wall_seconds / 1e6 : 0.0;
    json summary = {
        {"firmware",
         {{"path", options.firmware.string()},
          {"sha256", sha256},
          {"flash_bytes", elf.memory_use().flash_bytes()},
          {"ram_bytes", elf.memory_use().ram_bytes()}}},
        {"case", options.test_case},
        {"cycles_total", result.cycles_total},
        {"clock_hz", core.clock_hz()},
        {"sim_seconds", sim_s},
        {"wall_seconds", result.wall_seconds},
        {"mcycles_per_s", mcycles_per_s},
        {"exit_reason", to_string(result.exit)},
        {"exit_message", result.message},
        {"ready_cycle", result.ready_cycle ? json(*result.ready_cycle) : json(nullptr)},
        {"uart",
         {{"bytes", uart.received().size()},
          {"cycles_per_byte", uart.cycles_per_byte()},
          {"timing", options.uart_timing == hil::UartTiming::kChip ? "chip" : "simavr"},
          {"bytes_not_delivered", uart.pending()}}},
        {"firmware_report", report_json(result.report)},
        {"simavr_log",
         {{"errors", core.log().errors()},
          {"warnings", core.log().warnings()},
          {"first_messages", core.log().first_messages()}}},
    };
    write_file_atomic(options.out_dir / "uart.txt", result.uart_text);
    write_file_atomic(options.out_dir / "eeprom.bin",
                      std::string_view(reinterpret_cast<const char*>(result.eeprom.data()),
                                       result.eeprom.size()));
    write_file_atomic(options.out_dir / "summary.json", summary.dump(2) + "\n");
    return result;
}

}  // namespace ddmr::tools
