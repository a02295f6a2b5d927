"""Monte-Carlo over manufacturing tolerances with the real firmware in the
loop (docs/python.md, "A Monte-Carlo study"): N plants whose motors' armature
resistance and torque constant (= back-EMF constant in SI units) each lie
uniformly within +-10 % of the defaults (seeded), each running the reference sketch's case 1 (the 0.6 m
circle) in the HIL on a Dask LocalCluster. What fraction ends within 5 cm of
the goal the firmware reports (Gx, Gy)?

    PYTHONPATH=build/python /usr/bin/python3 tools/python/examples/monte_carlo_circle.py \\
        --firmware build/firmware/ddmr_tracking.elf --plants 200 --out build/bench/monte_carlo.json

`make bench` runs it with 200 plants."""

import argparse
import json
import math
import os
import re
import sys
import time

import numpy as np

from ddmr_hil import sweep
from ddmr_hil.sweep import to_csv

DEFAULTS = {  # plant/params/default.yaml
    "motor1": {"resistance_ohm": 5.32, "back_emf_V_s_per_rad": 0.00384, "torque_N_m_per_A": 0.00384},
    "motor2": {"resistance_ohm": 5.41, "back_emf_V_s_per_rad": 0.00384, "torque_N_m_per_A": 0.00384},
}
GOAL = re.compile(rb"Gx,(-?[0-9.]+),Gy,(-?[0-9.]+)")


def goal_miss(session):
    """The end pose's distance from the goal the firmware's report states."""
    m = GOAL.search(session.serial.text)
    if m is None:
        return {"goal_x_m": float("nan"), "goal_y_m": float("nan"), "miss_m": float("nan")}
    gx, gy = float(m.group(1)), float(m.group(2))
    pose = session.truth.pose()
    return {"goal_x_m": gx, "goal_y_m": gy, "miss_m": math.hypot(pose.x_m - gx, pose.y_m - gy)}


def plants(n, seed, tolerance):
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        p = {}
        for motor, params in DEFAULTS.items():
            r = params["resistance_ohm"] * (1.0 + rng.uniform(-tolerance, tolerance))
            k = params["torque_N_m_per_A"] * (1.0 + rng.uniform(-tolerance, tolerance))  # K_t = K_a in SI units
            p[motor] = {"resistance_ohm": round(r, 9), "back_emf_V_s_per_rad": round(k, 9),
                        "torque_N_m_per_A": round(k, 9)}
        out.append(p)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--firmware", required=True)
    ap.add_argument("--plants", type=int, default=200)
    ap.add_argument("--tolerance", type=float, default=0.10, help="+- fraction of each default")
    ap.add_argument("--miss-m", type=float, default=0.05, help="within this of the goal counts")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--out", required=True, help="JSON summary; the table beside it as .csv")
    a = ap.parse_args(argv)
    start = time.monotonic()
    table = sweep(plants(a.plants, a.seed, a.tolerance), firmware=a.firmware, case=1, measure=goal_miss,
                  workers=a.workers, seed=a.seed)
    wall = time.monotonic() - start
    miss = np.array(table["miss_m"], dtype=float)
    complete = np.array([r == "report_complete" for r in table["exit_reason"]])
    within = int(np.sum(complete & (miss <= a.miss_m)))
    summary = {
        "plants": a.plants, "tolerance": a.tolerance, "miss_limit_m": a.miss_m, "completed": int(complete.sum()),
        "within": within, "fraction_within": within / a.plants, "miss_median_m": float(np.nanmedian(miss)),
        "miss_max_m": float(np.nanmax(miss)), "wall_s": wall, "workers": a.workers or os.cpu_count(),
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(os.path.splitext(a.out)[0] + ".csv", "w", encoding="utf-8") as f:
        f.write(to_csv(table))
    with open(a.out, "w", encoding="utf-8") as f:
        json.dump(summary, f, indent=2)
        f.write("\n")
    print(f"monte carlo: {within}/{a.plants} plants ({100 * within / a.plants:.1f} %) end case 1 within "
          f"{100 * a.miss_m:.0f} cm of the goal (median miss {1000 * summary['miss_median_m']:.1f} mm, "
          f"max {1000 * summary['miss_max_m']:.1f} mm); {wall:.0f} s on {summary['workers']} workers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
