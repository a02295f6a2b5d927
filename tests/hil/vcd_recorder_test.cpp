// VcdRecorder on a RobotRig: in averaged PWM mode the enable pins still show
// the phase-correct waveform, the ISR signals are the ELF's handled vectors,
// and a destroyed recorder leaves the rig running without it. (The full
// case-1 checks against summary.json and isr.json are in
// tests/tools/run_command_test.cpp.)
#include "hil/vcd_recorder.hpp"

#include <gtest/gtest.h>
#include <sim_avr.h>

#include <string>

#include "support/test_paths.hpp"
#include "support/vcd_reader.hpp"
#include "support/uno_board.hpp"

namespace ddmr::hil {
namespace {

TEST(VcdRecorder, AveragedModeStillDrawsThePhaseCorrectWaveform) {
    const auto elf = ElfImage::read(test::firmware_elf());
    RigConfig config;
    config.coupler.mode = plant::DriveMode::averaged;
    RobotRig rig(elf, config);
    std::string text;
    VcdConfig vcd_config;
    vcd_config.clock_hz = rig.core().clock_hz();
    VcdWriter writer([&text](std::string_view s) { text.append(s); }, vcd_config);
    Cycles sent = 0;
    {
        VcdRecorder recorder(rig, elf, writer);
        rig.coupler().set_boundary_hook([&recorder](Cycles c) { recorder.on_boundary(c); });
        ASSERT_EQ(rig.core().run_until_return_from(elf.require("delay"), s_to_cycles(6.0, test::kUnoClockHz)), RunStop::kCondition);
        sent = rig.core().cycle();
        rig.uart().send("1");
        rig.core().run_until(sent + s_to_cycles(0.5, test::kUnoClockHz));  // 0.5 s of the circle: ~245 PWM periods
        recorder.finish();
        rig.coupler().set_boundary_hook(nullptr);
    }
    // Unhooked: the rig runs on, nothing reaches the finished writer (it would throw).
    EXPECT_NO_THROW(rig.core().run_until(rig.core().cycle() + s_to_cycles(0.1, test::kUnoClockHz)));

    const test::VcdFile f = test::parse_vcd(text);
    for (const char* name : {"isr_INT0", "isr_INT1", "isr_TIMER0_OVF", "isr_USART_RX", "isr_USART_UDRE"}) {
        EXPECT_TRUE(f.has(std::string("ddmr_hil.isr.") + name)) << name;
    }
    EXPECT_FALSE(f.has("ddmr_hil.isr.isr_TIMER1_OVF"));  // no handler in the sketch
    // Every complete pulse on pin 11 after the case byte lasts 2 x OCR x 64
    // cycles: a multiple of 8,000 ns (1 ns of rounding down either way).
    const test::VcdVar& d11 = f.var("ddmr_hil.uno.D11_left_PWM");
    const uint64_t sent_ns = VcdWriter::cycles_to_ns(sent, test::kUnoClockHz);
    std::size_t pulses = 0;
    for (std::size_t i = 1; i + 1 < d11.changes.size(); ++i) {
        if (d11.changes[i].value != 1 || d11.changes[i].time < sent_ns) continue;
        const uint64_t width = d11.changes[i + 1].time - d11.changes[i].time;
        if (width >= 2'040'000) continue;  // held high across periods (OCR = TOP)
        ++pulses;
        EXPECT_LE(std::min(width % 8000, 8000 - width % 8000), 1u) << "pulse at " << d11.changes[i].time;
    }
    EXPECT_GT(pulses, 200u);
    EXPECT_GT(test::edge_count(f.var("ddmr_hil.uno.D3_left_OUT")), 10u);  // the wheel turns
}

// A board part's outputs are signals: tests/firmware/shift_fixture.c latches
// 0x06 into a 74HC595 called sr; Q1 and Q2 rise at the latch, Q0 stays low.
TEST(VcdRecorder, DrawsEachPartOutputFromTheCycleItChanges) {
    const auto elf = ElfImage::read(test::test_firmware_dir() / "shift_fixture.elf");
    RigConfig config;
    config.board.parts.push_back(PartEntry{"sr", "74hc595", 0,
                                           {{"DS", {"8", 8, 0}}, {"SHCP", {"4", 4, 0}}, {"STCP", {"12", 12, 0}},
                                            {"OE", {"7", 7, 0}}, {"MR", {"high", -1, 0}}}});
    config.board.wheel[1].motor[DriverRole::dir].pin = 9;  // the default's D13 is free, D12 is the latch
    config.board.wheel[0].motor[DriverRole::dir].pin = 13;
    RobotRig rig(elf, config);
    std::string text;
    VcdConfig vcd_config;
    vcd_config.clock_hz = rig.core().clock_hz();
    VcdWriter writer([&text](std::string_view s) { text.append(s); }, vcd_config);
    {
        VcdRecorder recorder(rig, elf, writer);
        rig.core().run_until(1000);  // past the start-up's .bss clearing
        const auto at = [&](const char* name) { return static_cast<uint16_t>(elf.require(name).address); };
        rig.core().raw()->data[at("data")] = 0x06;
        rig.core().raw()->data[at("request")] = 1;
        rig.core().run_until(30000);
        ASSERT_EQ(rig.core().raw()->data[at("done")], 1);
        recorder.finish();
    }
    const test::VcdFile f = test::parse_vcd(text);
    ASSERT_TRUE(f.has("ddmr_hil.sr.Q1")) << text.substr(0, 2000);
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.sr.Q0")), 0u);
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.sr.Q1")), 1u);
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.sr.Q2")), 1u);
    EXPECT_EQ(f.var("ddmr_hil.sr.Q1").changes.back().value, 1u);
    EXPECT_EQ(f.var("ddmr_hil.sr.Q1").changes.back().time, f.var("ddmr_hil.sr.Q2").changes.back().time);
    // The part's own pins: SHCP clocks 8 bits (up, then down and up 7 times:
    // 15 edges), STCP latches once (1 edge), DS carries 0x06 MSB first
    // (0 0 0 0 0 1 1 0: 2 edges).
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.uno.D4_sr_SHCP")), 15u);
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.uno.D12_sr_STCP")), 1u);
    EXPECT_EQ(test::edge_count(f.var("ddmr_hil.uno.D8_sr_DS")), 2u);
    // Destroyed, the recorder left no listener on the part: the rig runs on.
    EXPECT_NO_THROW(rig.core().run_until(rig.core().cycle() + 1000));
}

}  // namespace
}  // namespace ddmr::hil
