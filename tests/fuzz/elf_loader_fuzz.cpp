// Fuzz target: the firmware front end on arbitrary bytes: ElfImage (libelf
// checks), the scan for calls to address 0, and, for what it accepts,
// simavr's own ELF loader (AvrCore) with the reset monitor watching. It must
// refuse with an exception naming the file, never crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <string>

#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"
#include "hil/reset_monitor.hpp"
#include "hil/zero_calls.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    static const std::string path = "/tmp/ddmr-fuzz-elf-" + std::to_string(::getpid()) + ".elf";
    {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    }
    try {
        const auto elf = ddmr::hil::ElfImage::read(path);
        (void)ddmr::hil::find_zero_calls(elf);
        elf.require_mcu(ddmr::hil::atmega328p_mcu());
        ddmr::hil::AvrCore core(elf);
        ddmr::hil::ResetMonitor resets(core);
        resets.set_warning_sink([](const std::string&) {});
        core.run_until(1000);
    } catch (const std::exception&) {
    }
    return 0;
}
