// What the world costs (issue 33's goal: at most 10 % slower with 50 walls):
// the same sketch with five wall-seeing sensors, run by `ddmr-hil scenario`
// for 20 simulated seconds in a world of 0 walls and in one of 50, three
// rounds interleaved (A B A B A B); the median wall seconds of each and their
// ratio (counter `ratio_50_to_0`, the goal <= 1.10).
//
// The sketch: firmware/examples/bumper_wanderer_l9110 (it drives, backs off
// and turns at each bump). The board adds to its two bumpers two IR obstacle
// modules and an HC-SR04 on the servo-less front: five sensors, each reading
// the world at every plant step (the sonar when pinged: this sketch never
// pings it, so it costs nothing; the IR modules and bumpers cast every step).
// The 50-wall world: the 1.5 m arena's 4 sides and 46 short walls in a ring
// 3 m out (every sensor and the contact check still test each of them).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "child_run.hpp"

namespace {

namespace fs = std::filesystem;

using ddmr::bench::ScratchDir;
using ddmr::bench::write_text;

std::string board_yaml() {
    return "board: uno\n"
           "wheels:\n"
           "  left:  {motor: {driver: l9110, IN1: 5, IN2: 6}, encoder: {type: single, OUT: 2}}\n"
           "  right: {motor: {driver: l9110, IN1: 9, IN2: 10}, encoder: {type: single, OUT: 3}}\n"
           "parts:\n"
           "  - {name: bump_left,  type: bumper, OUT: 7, x_mm: 90, y_mm: 80, reach_mm: 3}\n"
           "  - {name: bump_right, type: bumper, OUT: 8, x_mm: 90, y_mm: -80, reach_mm: 3}\n"
           "  - {name: ir_left,  type: ir-obstacle, OUT: 11, x_mm: 90, y_mm: 40, heading_deg: 30}\n"
           "  - {name: ir_right, type: ir-obstacle, OUT: 12, x_mm: 90, y_mm: -40, heading_deg: -30}\n"
           "  - {name: sonar, type: ultrasonic, TRIG: A0, ECHO: A1, x_mm: 80}\n";
}

/// 0 walls, or the arena's 4 and 46 in a ring 3 m out.
std::string world_yaml(int walls) {
    if (walls == 0) return "floor: {reflectance: 0.8}\n";
    std::string y = "walls:\n  - {polygon_m: [[-0.75, -0.75], [0.75, -0.75], [0.75, 0.75], [-0.75, 0.75]]}\n";
    for (int k = 0; k < walls - 4; ++k) {
        const double a = 2.0 * M_PI * k / (walls - 4);
        const double b = a + 0.05;
        y += "  - {from_m: [" + std::to_string(3 * std::cos(a)) + ", " + std::to_string(3 * std::sin(a)) + "], to_m: [" +
             std::to_string(3 * std::cos(b)) + ", " + std::to_string(3 * std::sin(b)) + "]}\n";
    }
    return y;
}

std::string scenario_yaml(int walls) {
    return "name: walls" + std::to_string(walls) + "\ntimeout: 30s\nserial: {baud: 115200}\n" +
           "firmware: {sketch: bumper_wanderer_l9110/bumper_wanderer_l9110.ino}\n" +
           "board: board.yaml\nworld: world" + std::to_string(walls) + ".yaml\nsteps:\n  - delay: 20s\n";
}

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

void BM_WorldWallsCost(benchmark::State& state) {
    ScratchDir dir;
    // A scenario's paths are relative to its folder: the sketch is copied in.
    fs::create_directories(dir.path / "bumper_wanderer_l9110");
    fs::copy_file(fs::path(DDMR_BENCH_EXAMPLES) / "bumper_wanderer_l9110" / "bumper_wanderer_l9110.ino",
                  dir.path / "bumper_wanderer_l9110" / "bumper_wanderer_l9110.ino");
    write_text(dir.path / "board.yaml", board_yaml());
    const std::vector<int> worlds = {0, 50};
    for (const int w : worlds) {
        write_text(dir.path / ("world" + std::to_string(w) + ".yaml"), world_yaml(w));
        write_text(dir.path / ("s" + std::to_string(w) + ".yaml"), scenario_yaml(w));
    }
    const auto run = [&](int w) {
        return ddmr::bench::run_child({DDMR_BENCH_CLI, "scenario", "--worker", (dir.path / ("s" + std::to_string(w) + ".yaml")).string(),
                                       "--out", (dir.path / ("out" + std::to_string(w))).string()});
    };
    for (const int w : worlds) {  // warm-up: builds (or finds) the sketch, checks the run
        if (run(w).status != 0) {
            state.SkipWithError("a world scenario failed");
            return;
        }
    }
    std::vector<double> wall0, wall50;
    for (auto _ : state) {
        for (int round = 0; round < 3; ++round) {
            wall0.push_back(run(0).wall_s);
            wall50.push_back(run(50).wall_s);
        }
    }
    state.counters["wall_s_0_walls"] = median(wall0);
    state.counters["wall_s_50_walls"] = median(wall50);
    state.counters["ratio_50_to_0"] = median(wall50) / median(wall0);
}

}  // namespace

BENCHMARK(BM_WorldWallsCost)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();
BENCHMARK_MAIN();
