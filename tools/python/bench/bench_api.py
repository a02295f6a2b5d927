"""`make bench`: what the Python API costs (issue 34's goals).

1. Case 1 driven from Python (Session.run_contract + save_artifacts, in a new
   interpreter) against `ddmr-hil run --case 1`, ROUNDS rounds interleaved;
   the ratio of the medians of wall time. Goal: at most 1.05.
2. A Dask sweep of 16 plants (case 1) on a LocalCluster of 2 workers against
   1 worker; the speed-up of wall time. Goal: at least 1.7.

    PYTHONPATH=build/python /usr/bin/python3 tools/python/bench/bench_api.py --build build --out build/bench/python.json
"""

import statistics
import sys
import tempfile
import time

from bench_timing import parse_bench_args, timed, write_result
from ddmr_hil import grid, sweep


def case1_ratio(build, rounds):
    elf = f"{build}/firmware/ddmr_tracking.elf"
    with tempfile.TemporaryDirectory() as tmp:
        py = [sys.executable, "-c",
              "import sys; from ddmr_hil import Session; s = Session(firmware=sys.argv[1]); "
              "assert s.run_contract(case=1) == 'report_complete'; s.save_artifacts(sys.argv[2])",
              elf, f"{tmp}/py"]
        cli = [f"{build}/ddmr-hil", "run", "--case", "1", "--quiet", "--out", f"{tmp}/cli"]
        t_py, t_cli = [], []
        for _ in range(rounds):
            t_cli.append(timed(cli))
            t_py.append(timed(py))
    return {"python_median_s": statistics.median(t_py), "run_median_s": statistics.median(t_cli),
            "ratio": statistics.median(t_py) / statistics.median(t_cli), "rounds": rounds, "goal_max": 1.05}


def sweep_speedup(build):
    elf = f"{build}/firmware/ddmr_tracking.elf"
    plants = grid({"motor1.resistance_ohm": [5.0, 5.2, 5.4, 5.6], "motor2.resistance_ohm": [5.0, 5.2, 5.4, 5.6]})
    out = {}
    for workers in (1, 2):
        start = time.monotonic()
        sweep(plants, firmware=elf, case=1, workers=workers)
        out[f"workers_{workers}_s"] = time.monotonic() - start
    out["speedup"] = out["workers_1_s"] / out["workers_2_s"]
    out["plants"] = len(plants)
    out["goal_min"] = 1.7
    return out


def main():
    a = parse_bench_args()
    result = {"case1": case1_ratio(a.build, a.rounds), "sweep": sweep_speedup(a.build)}
    write_result(a.out, result)
    c, s = result["case1"], result["sweep"]
    print(f"python case 1: {c['python_median_s']:.2f} s vs run {c['run_median_s']:.2f} s: ratio {c['ratio']:.3f} "
          f"(goal <= 1.05)")
    print(f"dask sweep of {s['plants']}: 1 worker {s['workers_1_s']:.1f} s, 2 workers {s['workers_2_s']:.1f} s: "
          f"x{s['speedup']:.2f} (goal >= 1.7)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
