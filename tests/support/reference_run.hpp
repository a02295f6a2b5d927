#pragma once
// Runs the reference firmware through one case with the hil parts alone
// (AvrCore, UartLink, EepromPort), for tests that check what it printed and
// logged. Boots, waits for setup()'s delay(5000) to return, sends the case
// byte and runs until the end-of-run report is complete (or `limit_s`).
#include <optional>
#include <string>
#include <vector>

#include "hil/avr_core.hpp"
#include "hil/eeprom_port.hpp"
#include "hil/firmware_report.hpp"
#include "hil/uart_link.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {

struct ReferenceRun {
    std::vector<hil::UartByte> bytes;
    std::string text;
    hil::EepromImage eeprom;
    hil::Cycles ready_cycle = 0;
    hil::Cycles end_cycle = 0;
    hil::Cycles cycles_per_byte = 0;
    bool report_complete = false;
    hil::FirmwareReport report;
};

inline ReferenceRun run_reference_case(char case_byte,
                                       hil::UartTiming timing = hil::UartTiming::kChip,
                                       const std::optional<hil::EepromImage>& preload = std::nullopt,
                                       double limit_s = 40.0) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core, timing);
    hil::EepromPort eeprom(core);
    if (preload) eeprom.preload(*preload);
    hil::FirmwareReportParser parser(case_byte == '1');
    uart.set_listener([&](const hil::UartByte& b) {
        parser.feed(std::string_view(reinterpret_cast<const char*>(&b.value), 1));
        if (parser.complete() || parser.error()) core.request_stop();
    });
    ReferenceRun run;
    const auto limit = hil::s_to_cycles(limit_s, kUnoClockHz);
    if (core.run_until_return_from(elf.require("delay"), limit) == hil::RunStop::kCondition) {
        run.ready_cycle = core.cycle();
        uart.send(std::string(1, case_byte));
        core.run_until(limit);
    }
    run.bytes = uart.received();
    run.text = uart.text();
    run.eeprom = eeprom.read_all();
    run.end_cycle = core.cycle();
    run.cycles_per_byte = uart.cycles_per_byte();
    run.report_complete = parser.complete();
    run.report = parser.report();
    return run;
}

}  // namespace ddmr::test
