// AvrCore: the reference firmware boots at 16 MHz, runs to a cycle, stops on
// a function's return, and answers the case bytes as the sketch says.
#include "hil/avr_core.hpp"

#include <gtest/gtest.h>

#include <sim_irq.h>

#include "hil/eeprom_port.hpp"
#include "hil/uart_link.hpp"
#include "support/reference_run.hpp"
#include "support/test_paths.hpp"
#include "support/uno_board.hpp"

namespace ddmr::test {
namespace {

TEST(AvrCore, RunsToTheRequestedCycle) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    EXPECT_EQ(core.clock_hz(), 16'000'000u);
    ASSERT_EQ(core.run_until(1'000'000), hil::RunStop::kReachedCycle);
    // The longest AVR instruction takes 5 cycles; an interrupt entry 4 more.
    EXPECT_GE(core.cycle(), 1'000'000u);
    EXPECT_LT(core.cycle(), 1'000'010u);
    EXPECT_NEAR(core.seconds(), 0.0625, 1e-6);
}

TEST(AvrCore, SetSramWritesSramOnlyAsADebuggerDoes) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    core.set_sram(0x100, 0xA5);  // the ATmega328P's first SRAM byte
    EXPECT_EQ(core.data(0x100), 0xA5);
    core.set_sram(0x8FF, 0x5A);  // RAMEND
    EXPECT_EQ(core.data(0x8FF), 0x5A);
    EXPECT_THROW(core.set_sram(0x25, 1), std::out_of_range);   // PORTB: an I/O register, not SRAM
    EXPECT_THROW(core.set_sram(0x900, 1), std::out_of_range);  // past RAMEND
}

// The step watch sees every instruction once, however the run is cut into
// run_until calls: 200,000 cycles in one call and in 1000 calls of 200 cycles
// (stops land mid-batch, as the coupler's do) give the same count, and the
// watch switched off returns the core to batched running.
TEST(AvrCore, TheStepWatchSeesEveryInstructionAcrossRunUntilCalls) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const auto count = [&](hil::Cycles chunk) {
        hil::AvrCore core(elf);
        uint64_t calls = 0;
        core.set_step_watch([](void* n) { ++*static_cast<uint64_t*>(n); }, &calls);
        for (hil::Cycles c = chunk; c <= 200'000; c += chunk) core.run_until(c);
        core.set_step_watch(nullptr, nullptr);
        const uint64_t before = calls;
        core.run_until(300'000);
        EXPECT_EQ(calls, before);  // off: never called
        EXPECT_GE(core.cycle(), 300'000u);
        return calls;
    };
    const uint64_t whole = count(200'000);
    EXPECT_GT(whole, 40'000u);  // an instruction takes 1..5 cycles
    EXPECT_EQ(count(200), whole);
}

TEST(AvrCore, SetupReturnsFromItsFiveSecondDelay) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    const auto stop = core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz));
    ASSERT_EQ(stop, hil::RunStop::kCondition);
    // delay(5000) is called a fraction of a millisecond after reset (init(),
    // pinMode, attachInterrupt, Serial.begin) and lasts 5000 ms of timer-0
    // time; the return is seen within a sample period and a loop pass.
    EXPECT_GT(core.seconds(), 5.0);
    EXPECT_LT(core.seconds(), 5.002);
    // The PC is back in main (setup() is inlined there by LTO).
    const auto fn = elf.function_at(core.pc());
    ASSERT_TRUE(fn.has_value());
    EXPECT_NE(fn->name, "delay");
}

TEST(AvrCore, StopAfterStopsAtTheExactCycle) {
    hil::AvrCore core(hil::ElfImage::read(firmware_elf()));
    core.run_until(1000);
    const auto start = core.cycle();
    core.stop_after(5000);
    EXPECT_EQ(core.run_until(1'000'000), hil::RunStop::kCondition);
    EXPECT_GE(core.cycle(), start + 5000);
    EXPECT_LT(core.cycle(), start + 5010);
}

// A stop a part requests from an I/O callback ends the run right after the
// instruction that raised it, however simavr batches instructions: with
// batches of up to 100,000 cycles and of one instruction, init()'s first
// write of TCCR0B stops the run at the same cycle, within an instruction of
// the write.
TEST(AvrCore, ARequestedStopEndsTheRunAfterTheInstructionThatAskedForIt) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    const auto stop_cycle = [&](hil::Cycles run_cycle_limit) {
        hil::AvrCoreConfig config;
        config.run_cycle_limit = run_cycle_limit;
        hil::AvrCore core(elf, config);
        struct Watch {
            hil::AvrCore* core;
            hil::Cycles written = 0;
        } watch{&core};
        const uint16_t tccr0b = core.mcu().timers.front().tccrb;
        const auto notify = [](avr_irq_t* /*irq*/, uint32_t /*value*/, void* param) {
            auto* w = static_cast<Watch*>(param);
            if (w->written == 0) w->written = w->core->cycle();
            w->core->request_stop();
        };
        core.watch_io(tccr0b, notify, &watch, hil::AvrCore::IoReads::kMatter);
        EXPECT_EQ(core.run_until(1'000'000), hil::RunStop::kCondition);
        EXPECT_GT(watch.written, 0U);
        EXPECT_LE(core.cycle(), watch.written + 5);  // the longest instruction: 5 cycles
        core.unwatch_io(tccr0b, notify, &watch, hil::AvrCore::IoReads::kMatter);
        return core.cycle();
    };
    EXPECT_EQ(stop_cycle(100'000), stop_cycle(1));
}

TEST(AvrCore, ResetRestartsTheFirmwareAndKeepsTimeAndEeprom) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::EepromPort eeprom(core);
    hil::EepromImage image = hil::EepromPort::erased(hil::atmega328p_mcu());
    image[7] = 0x42;
    eeprom.preload(image);
    int calls = 0;
    core.add_reset_listener(&calls, [&calls] { ++calls; });
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz)), hil::RunStop::kCondition);
    const hil::Cycles before = core.cycle();
    core.stop_after(1000);  // a cycle timer: a reset cancels it
    core.reset();
    EXPECT_EQ(calls, 1);
    EXPECT_EQ(core.resets(), 1U);
    EXPECT_EQ(core.pc(), 0U);
    EXPECT_EQ(core.cycle(), before);  // AVR time runs on
    EXPECT_EQ(core.stack_pointer(), hil::atmega328p::kRamEnd);
    EXPECT_EQ(core.data(hil::atmega328p::reg::kUcsr0B) & 0x10, 0);  // RXEN0 off until Serial.begin again
    EXPECT_EQ(core.run_until(before + 5000), hil::RunStop::kReachedCycle);  // the stop timer is gone
    EXPECT_EQ(eeprom.read_all()[7], 0x42);
    // The firmware boots again: setup()'s delay(5000) returns 5 s after the reset.
    ASSERT_EQ(core.run_until_return_from(elf.require("delay"), before + hil::s_to_cycles(6.0, kUnoClockHz)),
              hil::RunStop::kCondition);
    EXPECT_GT(core.seconds() - hil::cycles_to_s(before, kUnoClockHz), 5.0);
    EXPECT_LT(core.seconds() - hil::cycles_to_s(before, kUnoClockHz), 5.002);
    core.remove_reset_listener(&calls);
    core.reset();
    EXPECT_EQ(calls, 1);
}

TEST(AvrCore, Case1PrintsItsBannerThenEndAfterBootingSixSeconds) {
    // As the issue states it: boot for 6 simulated seconds, send '1'.
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    core.run_until(hil::s_to_cycles(6.0, kUnoClockHz));
    uart.send("1");
    core.run_until(hil::s_to_cycles(6.0 + 13.0, kUnoClockHz));
    const std::string text = uart.text();
    const auto banner = text.find("0.6m\r\n");
    ASSERT_NE(banner, std::string::npos) << text;
    const auto end = text.find("END\r\n");
    ASSERT_NE(end, std::string::npos) << text;
    EXPECT_LT(banner, end);
    // 1200 iterations of at least 9 ms (delay(9)) lie between the two.
    const auto end_byte = uart.received()[end];
    EXPECT_GT(hil::cycles_to_s(end_byte.cycle, kUnoClockHz), 6.0 + 1200 * 0.009);
}

TEST(AvrCore, Case2PrintsItsBanner) {
    const auto run = run_reference_case('2');
    ASSERT_TRUE(run.report_complete) << run.text;
    EXPECT_EQ(run.text.rfind("0.4m\r\nEND\r\n", 0), 0u) << run.text;
    EXPECT_EQ(run.report.banner, "0.4m");
}

TEST(AvrCore, AnyOtherByteIsAnsweredWithX) {
    const auto elf = hil::ElfImage::read(firmware_elf());
    hil::AvrCore core(elf);
    hil::UartLink uart(core);
    core.run_until_return_from(elf.require("delay"), hil::s_to_cycles(6.0, kUnoClockHz));
    uart.send("3");
    core.run_until(core.cycle() + hil::s_to_cycles(0.01, kUnoClockHz));
    EXPECT_EQ(uart.text(), "X\r\n");
}

}  // namespace
}  // namespace ddmr::test
