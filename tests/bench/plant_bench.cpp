// Plant cost: one Robot::step and 12 s of simulated plant, in ns per step.
// Compare with simavr: the HIL steps the plant every 1000 AVR cycles
// (62.5 us); tools/bench_table.py divides by bare simavr's time for them.
#include <benchmark/benchmark.h>

#include <cstdint>

#include "plant/pwm_waveform.hpp"
#include "plant/robot.hpp"

namespace {

using namespace ddmr::plant;

RobotInput input(DriveMode mode, double duty) {
    RobotInput in;
    in.mode = mode;
    for (BridgeInput& b : in.bridge) b = BridgeInput{BridgeState::forward, duty, true};
    return in;
}

/// One HIL coupling step (1000 cycles = 62.5 us), averaged mode, wheels turning.
void BM_PlantStepAveraged(benchmark::State& state) {
    Robot r;
    EdgeBuffer e;
    r.set_input(input(DriveMode::averaged, 0.6));
    const double dt = cycles_to_s(1000);
    for (int k = 0; k < 10000; ++k) r.step(dt, e), e.clear();  // reach speed
    for (auto _ : state) {
        e.clear();
        benchmark::DoNotOptimize(r.step(dt, e));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PlantStepAveraged);

/// One step of a given length in AVR cycles, switched mode, enable high.
void BM_PlantStepSwitched(benchmark::State& state) {
    Robot r;
    EdgeBuffer e;
    r.set_input(input(DriveMode::switched, 1.0));
    for (int k = 0; k < 10000; ++k) r.step(cycles_to_s(1000), e), e.clear();
    const double dt = cycles_to_s(state.range(0));
    for (auto _ : state) {
        e.clear();
        benchmark::DoNotOptimize(r.step(dt, e));
    }
    state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_PlantStepSwitched)->Arg(16)->Arg(160)->Arg(1000)->Arg(1600);

/// 12 s of plant with the real 490 Hz PWM at 50 %, split at every PWM edge
/// and every 1000 cycles, as the HIL drives it.
void BM_Plant12sSwitched(benchmark::State& state) {
    std::int64_t steps = 0;
    for (auto _ : state) {
        Robot r;
        EdgeBuffer e;
        const PhaseCorrectPwm pwm{128, 0};
        RobotInput in = input(DriveMode::switched, pwm.duty());
        const std::int64_t end = s_to_cycles(12.0);
        const std::int64_t max_step = 1000;  // the HIL's coupling step
        for (std::int64_t c = 0; c < end;) {
            const std::int64_t next = std::min({end, c + max_step, pwm.next_edge_after(c)});
            for (BridgeInput& b : in.bridge) {
                b.state = pwm.level_at(c) ? BridgeState::forward : BridgeState::coast;
            }
            r.set_input(in);
            e.clear();
            benchmark::DoNotOptimize(r.step(cycles_to_s(next - c), e));
            c = next;
            ++steps;
        }
    }
    state.counters["ns_per_step"] = benchmark::Counter(
        static_cast<double>(steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["steps"] = benchmark::Counter(static_cast<double>(steps),
                                                 benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_Plant12sSwitched)->Unit(benchmark::kMillisecond);

/// 12 s of plant in averaged mode at the default step.
void BM_Plant12sAveraged(benchmark::State& state) {
    std::int64_t steps = 0;
    for (auto _ : state) {
        Robot r;
        EdgeBuffer e;
        r.set_input(input(DriveMode::averaged, 0.5));
        const double h = r.params().stepper.max_step_s;
        const auto n = static_cast<std::int64_t>(12.0 / h);
        for (std::int64_t k = 0; k < n; ++k) {
            e.clear();
            benchmark::DoNotOptimize(r.step(h, e));
        }
        steps += n;
    }
    state.counters["ns_per_step"] = benchmark::Counter(
        static_cast<double>(steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_Plant12sAveraged)->Unit(benchmark::kMillisecond);

}  // namespace
