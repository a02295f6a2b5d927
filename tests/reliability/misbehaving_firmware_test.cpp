// Firmwares that misbehave (tests/reliability/firmwares/): each run ends with
// its own reason on stdout/result.json, exit code 3 (1 for one that only never prints what a wait-serial waits for), and what the firmware
// printed before is kept in uart.txt (issue 9).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <fstream>
#include <string>

#include "hil/eeprom_port.hpp"
#include "hil/eeprom_write_timing.hpp"
#include "hil/elf_image.hpp"
#include "support/process.hpp"
#include "support/temp_dir.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

namespace fs = std::filesystem;

struct Misbehaviour {
    const char* firmware;
    const char* reason;   ///< fragment of the one-line reason
    const char* printed;  ///< what uart.txt must start with
    const char* run_exit; ///< summary.json's exit_reason of `run` without a contract
};

void PrintTo(const Misbehaviour& m, std::ostream* os) { *os << m.firmware; }

class MisbehavingFirmware : public ::testing::TestWithParam<Misbehaviour> {};

TEST_P(MisbehavingFirmware, EndsWithItsReasonAndKeepsWhatItPrinted) {
    const Misbehaviour& m = GetParam();
    TempDir dir;
    const fs::path scenario = dir / "listen.yaml";
    std::ofstream(scenario) << "name: listen\ntimeout: 2s\nsteps:\n  - wait-serial: \"never printed\"\n";
    const fs::path elf = fs::path(DDMR_MISBEHAVING_DIR) / (std::string(m.firmware) + ".elf");
    const auto r = run_command(sh_quote(cli_path().string()) + " scenario " + sh_quote(scenario.string()) +
                               " --firmware " + sh_quote(elf.string()) + " --out " + sh_quote((dir / "out").string()));
    // A firmware that runs on but never prints the text is a failed wait
    // (exit 1, issue 19): the text never came. The others fail (exit 3).
    const bool never_came = std::string(m.run_exit) == "time_limit";
    EXPECT_EQ(r.exit_code, never_came ? 1 : 3) << r.out << r.err;
    EXPECT_NE(r.out.find(m.reason), std::string::npos) << r.out;
    const auto result = nlohmann::json::parse(read_text(dir / "out/listen/result.json"));
    EXPECT_EQ(result["verdict"], never_came ? "fail" : "firmware");
    EXPECT_NE(result["message"].get<std::string>().find(m.reason), std::string::npos) << result["message"];
    const std::string uart = read_text(dir / "out/listen/uart.txt");
    EXPECT_EQ(uart.substr(0, std::string(m.printed).size()), m.printed);
    EXPECT_TRUE(fs::exists(dir / "out/listen/failure_window.vcd"));
}

// The same firmwares through `run`, with no sketch contract: every failure
// reason ends the run the same way; one that only never finishes is a
// complete time-limited run (nothing said when it would end).
TEST_P(MisbehavingFirmware, RunWithoutAContractEndsWithTheSameReason) {
    const Misbehaviour& m = GetParam();
    TempDir dir;
    const fs::path elf = fs::path(DDMR_MISBEHAVING_DIR) / (std::string(m.firmware) + ".elf");
    const auto out = dir / "run";
    const auto r = run_command(sh_quote(cli_path().string()) + " run -q --seconds 2 --firmware " + sh_quote(elf.string()) +
                               " --out " + sh_quote(out.string()));
    const auto summary = nlohmann::json::parse(read_text(out / "summary.json"));
    EXPECT_EQ(summary["exit_reason"], m.run_exit);
    if (std::string(m.run_exit) == "time_limit") {
        EXPECT_EQ(r.exit_code, 0) << r.err;
    } else {
        EXPECT_EQ(r.exit_code, 3) << r.out << r.err;
        EXPECT_NE(r.err.find(summary["exit_message"].get<std::string>()), std::string::npos) << r.err;  // said on stderr
    }
    const std::string uart = read_text(out / "uart.txt");
    EXPECT_EQ(uart.substr(0, std::string(m.printed).size()), m.printed);
    EXPECT_TRUE(fs::exists(out / "isr.md"));
}

INSTANTIATE_TEST_SUITE_P(
    Reliability, MisbehavingFirmware,
    ::testing::Values(Misbehaviour{"crash_jump", "crashed at PC 0x", "jumping\r\n", "crashed"},
                      Misbehaviour{"invalid_opcode", "Invalid Opcode", "invalid\r\n", "simavr_error"},
                      Misbehaviour{"sleep_forever", "slept with interrupts off", "sleeping\r\n", "sleep_with_interrupts_off"},
                      Misbehaviour{"never_prints", "'never printed' never came: the scenario's timeout (2 simulated s) came first; received 0 bytes", "", "time_limit"},
                      Misbehaviour{"watchdog", "watchdog reset at cycle", "booted\r\n", "watchdog_reset"},
                      Misbehaviour{"stack_overflow", "stack overflow into .bss at cycle", "recursing\r\n", "stack_overflow"},
                      Misbehaviour{"reset_loop", "reset loop: the firmware restarted from address 0 without a reset more than 10 times", "booted\r\n", "reset_loop"},
                      Misbehaviour{"uart_flood", "'never printed' never came: the scenario's timeout (2 simulated s) came first; received 19", "FLOOD FLOOD", "time_limit"}),
    [](const ::testing::TestParamInfo<Misbehaviour>& param_info) { return std::string(param_info.param.firmware); });

TEST(MisbehavingFirmware, AFloodedUartIsReceivedInFull) {
    // The chip's 9600 baud is 16 MHz / (8 x 208) = 9615 baud: a 10-bit frame
    // every 16,640 cycles, so 2 s hold at most 1923 frames back to back.
    TempDir dir;
    const fs::path scenario = dir / "listen.yaml";
    std::ofstream(scenario) << "name: listen\ntimeout: 3s\nsteps:\n  - delay: 2s\n";
    const auto r = run_command(sh_quote(cli_path().string()) + " scenario " + sh_quote(scenario.string()) +
                               " --firmware " + sh_quote((fs::path(DDMR_MISBEHAVING_DIR) / "uart_flood.elf").string()) +
                               " --out " + sh_quote((dir / "out").string()));
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    const std::string uart = read_text(dir / "out/listen/uart.txt");
    EXPECT_GE(uart.size(), 1920U);
    EXPECT_LE(uart.size(), 1923U);
}

TEST(MisbehavingFirmware, AnEepromFloodIsCountedInBoundedMemory) {
    // eeprom_flood writes address n mod 1024 with (n / 8) mod 256, n = 0, 1, ...
    // With simavr's instant writes that is one write every few dozen cycles:
    // 0.5 s make far more than EepromWriteTiming records (kMaxRecordedWrites).
    // The list stops there; the count, and the latest write of every address
    // (what the EEPROM log's times need), stay exact.
    using hil::EepromWriteTiming;
    const auto elf = hil::ElfImage::read(fs::path(DDMR_MISBEHAVING_DIR) / "eeprom_flood.elf");
    hil::AvrCore core(elf);
    EepromWriteTiming timing(core, hil::EepromTimingMode::kInstant);
    const hil::EepromPort eeprom(core);
    core.run_until(hil::s_to_cycles(0.5, kUnoClockHz));
    const uint64_t n = timing.write_count();
    ASSERT_GT(n, EepromWriteTiming::kMaxRecordedWrites + 1024);
    EXPECT_FALSE(timing.all_writes_recorded());
    const auto& recorded = timing.writes();
    ASSERT_EQ(recorded.size(), EepromWriteTiming::kMaxRecordedWrites);
    for (std::size_t k = 0; k < recorded.size(); ++k) {  // the first ones, in order
        ASSERT_EQ(recorded[k].address, k % 1024) << k;
        ASSERT_EQ(recorded[k].value, static_cast<uint8_t>(k / 8)) << k;
        if (k > 0) {
            ASSERT_GT(recorded[k].cycle, recorded[k - 1].cycle) << k;
        }
    }
    const auto latest = timing.latest_writes();
    ASSERT_EQ(latest.size(), 1024U);
    const hil::EepromImage image = eeprom.read_all();
    for (std::size_t k = 0; k < latest.size(); ++k) {
        EXPECT_EQ(latest[k].value, image[latest[k].address]) << "address " << latest[k].address;
        if (k > 0) {
            EXPECT_GT(latest[k].cycle, latest[k - 1].cycle) << k;
        }
    }
    // The newest is write n - 1; the oldest of the latest is write n - 1024.
    EXPECT_EQ(latest.back().address, (n - 1) % 1024);
    EXPECT_EQ(latest.back().value, static_cast<uint8_t>((n - 1) / 8));
    EXPECT_EQ(latest.front().address, (n - 1024) % 1024);
    EXPECT_EQ(latest.front().value, static_cast<uint8_t>((n - 1024) / 8));
}

}  // namespace
}  // namespace ddmr::test
