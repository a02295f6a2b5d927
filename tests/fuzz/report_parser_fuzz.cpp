// Fuzz target: the firmware report parser (hil/firmware_report) on arbitrary
// UART bytes, fed in two pieces (the parser is incremental).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "hil/firmware_report.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    for (const bool dump : {true, false}) {
        ddmr::hil::FirmwareReportParser parser(dump);
        const std::size_t cut = size / 3;
        parser.feed(text.substr(0, cut));
        parser.feed(text.substr(cut));
        (void)parser.complete();
        (void)parser.report();
    }
    return 0;
}
