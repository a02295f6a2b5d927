#!/usr/bin/python3
"""`make bench`: what fast-forward gains (issue 35's goals, docs/fast-forward.md).

1. `ddmr-hil run --case 1` with fast-forward against --no-fast-forward,
   ROUNDS rounds interleaved; the ratio of the medians of wall time (goal
   >= 3) and the share of cycles skipped from summary.json (goal >= 0.70).
2. The shipped scenario suite and the examples' (tests/scenarios,
   firmware/examples/*/scenario.yaml, -j 2) both ways; the ratio of the
   medians (goal >= 2.5).

    /usr/bin/python3 tools/python/bench/bench_fast_forward.py --build build --out build/bench/fast_forward.json
"""

import glob
import json
import statistics
import sys
import tempfile
from pathlib import Path

from bench_timing import parse_bench_args, timed, write_result


def interleaved(on_cmd, off_cmd, rounds):
    on, off = [], []
    for _ in range(rounds):
        on.append(timed(on_cmd))
        off.append(timed(off_cmd))
    return {"on_median_s": statistics.median(on), "off_median_s": statistics.median(off),
            "ratio": statistics.median(off) / statistics.median(on), "rounds": rounds}


def case1(build, rounds):
    with tempfile.TemporaryDirectory() as tmp:
        run = [f"{build}/ddmr-hil", "run", "--case", "1", "--quiet"]
        r = interleaved(run + ["--out", f"{tmp}/on"], run + ["--out", f"{tmp}/off", "--no-fast-forward"], rounds)
        ff = json.loads(Path(f"{tmp}/on/summary.json").read_text())["fast_forward"]
    r.update({"skipped_share": ff["skipped_share"], "skips": ff["skips"], "goal_ratio_min": 3.0,
              "goal_skipped_min": 0.70})
    return r


def suites(build, source, rounds):
    files = sorted(glob.glob(f"{source}/tests/scenarios/*.yaml")) + sorted(
        glob.glob(f"{source}/firmware/examples/*/scenario.yaml"))
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [f"{build}/ddmr-hil", "scenario", *files, "-j", "2"]
        r = interleaved(cmd + ["--out", f"{tmp}/on"], cmd + ["--out", f"{tmp}/off", "--no-fast-forward"], rounds)
    r.update({"scenarios": len(files), "goal_ratio_min": 2.5})
    return r


def main():
    a = parse_bench_args(with_source=True)
    result = {"case1": case1(a.build, a.rounds), "suite": suites(a.build, a.source, max(1, a.rounds // 2))}
    write_result(a.out, result)
    c, s = result["case1"], result["suite"]
    print(f"case 1: {c['on_median_s']:.2f} s with fast-forward, {c['off_median_s']:.2f} s without: "
          f"x{c['ratio']:.2f} (goal >= 3); {100 * c['skipped_share']:.1f} % of cycles skipped (goal >= 70 %)")
    print(f"{s['scenarios']} scenarios: {s['on_median_s']:.1f} s with, {s['off_median_s']:.1f} s without: "
          f"x{s['ratio']:.2f} (goal >= 2.5)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
