#pragma once
// tests/firmware/profile_fixture.c on the Uno, profiled from reset with
// `mark` as the loop mark and INT0 edges every 997 cycles (they land in every
// function of the loop), run for a given number of cycles: the hand-counted
// firmware of tests/hil/function_profiler_test.cpp, for the tests of the
// profile's outputs. Per loop iteration (n of them) and per INT0 interrupt
// (e of them), in cycles:
//   leaf 8, middle 10 + leaf, tailer 4 + leaf, mark 6, main 14: period 50;
//   vector JMP 3 + __vector_1 10 + leaf 8: interrupt 21.
#include <gtest/gtest.h>

#include "function_profile_output.hpp"
#include "hil/avr_core.hpp"
#include "hil/elf_image.hpp"
#include "hil/function_profiler.hpp"
#include "hil/loop_profiler.hpp"
#include "profile_lines.hpp"
#include "support/square_wave_input.hpp"
#include "support/test_paths.hpp"

namespace ddmr::test {

struct ProfiledFixture {
    static constexpr hil::Cycles kPeriod = 50;     ///< one loop iteration
    static constexpr hil::Cycles kInterrupt = 21;  ///< one INT0 interrupt
    static constexpr hil::Cycles kLeaf = 8;

    hil::ElfImage elf;
    hil::AvrCore core;
    hil::FunctionProfiler profiler;
    hil::LoopProfiler loop;
    SquareWaveInput wave;

    explicit ProfiledFixture(hil::Cycles cycles)
        : elf(hil::ElfImage::read(test_firmware_dir() / "profile_fixture.elf")),
          core(elf),
          profiler(core),  // before the first instruction: the whole stack
          loop(core, elf.require("mark")),
          wave(core, 'D', 2, 997) {
        loop.set_iteration_listener([this](bool completed) { profiler.on_loop_boundary(completed); });
        loop.arm();
        core.run_until(cycles);
    }

    /// Completed loop iterations and the INT0 interrupts inside them.
    uint64_t iterations() const { return profiler.control_loop().iterations; }
    uint64_t interrupts() const {
        return profiler.control_loop().functions[*profiler.map().find("__vector_1")].calls;
    }

    /// Enough iterations and interrupts for a hand count to cover every edge
    /// (30,000 cycles: ~550 iterations, ~30 interrupts).
    void expect_busy() const {
        EXPECT_GT(iterations(), 400u);
        EXPECT_GT(interrupts(), 10u);
    }

    /// What the profile's outputs need: the Uno's clock, the mark, the ELF's lines.
    tools::FunctionProfileContext context() const {
        tools::FunctionProfileContext c{16'000'000, "mark", {}, {}};
        c.lines = tools::profile_lines(elf.path(), profiler);
        return c;
    }
};

}  // namespace ddmr::test
