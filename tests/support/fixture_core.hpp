#pragma once
// A C test fixture (tests/firmware/<name>.elf) running in an AvrCore, with
// its globals read and written by name: for the tests of the parts'
// capabilities (PinProbe, PinDriver, AdcInput, TwiSlave), whose fixtures
// take requests and leave results in globals.

#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <sim_avr.h>

#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {

struct FixtureCore {
    hil::ElfImage elf;
    hil::AvrCore core;

    explicit FixtureCore(const std::string& name, hil::BoardModel board = hil::BoardModel::uno)
        : elf(hil::ElfImage::read(test_firmware_dir() / (name + ".elf"))), core(elf, hil::AvrCoreConfig{board}) {}

    /// The data-space address of global `name`.
    uint16_t address(const std::string& name) const {
        const auto sym = elf.find(name);
        if (!sym || !sym->is_object) throw std::invalid_argument("fixture has no global " + name);
        return static_cast<uint16_t>(sym->address);
    }
    uint8_t u8(const std::string& name, std::size_t index = 0) const {
        return core.data(static_cast<uint16_t>(address(name) + index));
    }
    /// Element `index` of a little-endian uint16_t array (or the scalar).
    uint16_t u16(const std::string& name, std::size_t index = 0) const {
        const auto at = static_cast<uint16_t>(address(name) + 2 * index);
        return static_cast<uint16_t>(core.data(at) | (core.data(static_cast<uint16_t>(at + 1)) << 8));
    }
    std::vector<uint8_t> bytes(const std::string& name, std::size_t count) const {
        std::vector<uint8_t> out;
        for (std::size_t i = 0; i < count; ++i) out.push_back(u8(name, i));
        return out;
    }
    /// Writes a byte the firmware polls (a request to the fixture).
    void poke(const std::string& name, uint8_t value) { core.raw()->data[address(name)] = value; }
    /// The fixture's startup (.bss cleared) is over by then: requests poked
    /// earlier would be wiped.
    static constexpr hil::Cycles kPastStartup = 1000;

    /// Asks the fixture for `value` through the u8 global `request` and runs
    /// until it answers with the same value in `done` (at most `limit` cycles).
    bool handshake(const std::string& request, const std::string& done, uint8_t value, hil::Cycles limit) {
        if (core.cycle() < kPastStartup) core.run_until(kPastStartup);
        poke(request, value);
        return run_until_u8(done, value, limit);
    }

    /// Runs until the u8 global `name` equals `value`, at most `limit` cycles;
    /// false if it never does.
    bool run_until_u8(const std::string& name, uint8_t value, hil::Cycles limit) {
        const hil::Cycles end = core.cycle() + limit;
        while (u8(name) != value) {
            if (core.cycle() >= end) return false;
            core.run_until(core.cycle() + 16);
        }
        return true;
    }
};

/// `fn()` throws std::invalid_argument whose message contains `words`.
template <typename Fn>
void expect_invalid_argument(Fn&& fn, const std::string& words) {
    try {
        fn();
        ADD_FAILURE() << "no std::invalid_argument";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
}

}  // namespace ddmr::test
