// Host reference simulation cost: 12 s of case 1 (the 0.6 m circle) at the
// default plant step (1e-4 s), per model. The goal is "well under a second".
#include <benchmark/benchmark.h>

#include "tools/hostsim/host_sim.hpp"

namespace {

using namespace ddmr::hostsim;

void run_case1(benchmark::State& state, SimConfig c) {
    std::uint64_t steps = 0;
    for (auto _ : state) {
        const SimResult r = simulate(c);
        benchmark::DoNotOptimize(r.end_pose.x_m);
        steps += r.plant_steps;
    }
    state.counters["plant_steps"] =
        benchmark::Counter(static_cast<double>(steps), benchmark::Counter::kAvgIterations);
    state.counters["ns_per_step"] = benchmark::Counter(
        static_cast<double>(steps), benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

/// Control law every plant step, on the true pose, averaged PWM.
void BM_SimCase1Ideal(benchmark::State& state) { run_case1(state, config_for_case(1, Model::ideal)); }
BENCHMARK(BM_SimCase1Ideal)->Unit(benchmark::kMillisecond);

/// Every fidelity switch: control every 10 ms in float on the edge counts.
void BM_SimCase1Firmware(benchmark::State& state) { run_case1(state, config_for_case(1, Model::firmware)); }
BENCHMARK(BM_SimCase1Firmware)->Unit(benchmark::kMillisecond);

/// The firmware model with the 490 Hz PWM waveform (steps split at its edges).
void BM_SimCase1FirmwareSwitched(benchmark::State& state) {
    SimConfig c = config_for_case(1, Model::firmware);
    c.pwm = PwmModel::switched;
    run_case1(state, c);
}
BENCHMARK(BM_SimCase1FirmwareSwitched)->Unit(benchmark::kMillisecond);

/// The kinematic robot (no motors): the cost of the control law itself.
void BM_SimCase1IdealKinematic(benchmark::State& state) {
    SimConfig c = config_for_case(1, Model::ideal);
    c.kinematic_plant = true;
    run_case1(state, c);
}
BENCHMARK(BM_SimCase1IdealKinematic)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
