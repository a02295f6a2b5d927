#!/usr/bin/env python3
"""Soak: case 1 repeated for 1, 10 and 60 simulated minutes (issue 9).

Each length runs in its own `ddmr-hil scenario --worker` process (plant
coupled, ground truth streamed to truth.csv, the failure VCD window kept in
memory); the line per length gives the simulated time, wall time, Mcycles/s
and the process's peak RSS, which must stay flat as the run gets longer.

Usage: soak.py [--cli build/ddmr-hil] [--out DIR] [--minutes 1,10,60]
"""
import argparse
import json
import os
import subprocess
import time
from pathlib import Path


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cli", default="build/ddmr-hil")
    ap.add_argument("--out", default="out/soak")
    ap.add_argument("--minutes", default="1,10,60")
    a = ap.parse_args()
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    for minutes in (int(m) for m in a.minutes.split(",")):
        reps = int(minutes * 60 / 14.5) + 1  # case 1 + report + 2 s pause: about 14.5 s of AVR time
        steps = '  - write-serial: "1"\n  - wait-serial: "END"\n  - delay: 2s\n' * reps
        scenario = out / f"soak{minutes}.yaml"
        scenario.write_text(f"name: soak{minutes}\ntimeout: {minutes * 60 + 120}s\nsteps:\n{steps}")
        t0 = time.time()
        p = subprocess.Popen([a.cli, "scenario", "--worker", str(scenario), "--out", str(out / f"soak{minutes}")],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        _, status, usage = os.wait4(p.pid, 0)
        wall = time.time() - t0
        r = json.loads((out / f"soak{minutes}" / "result.json").read_text())
        truth_mb = (out / f"soak{minutes}" / "truth.csv").stat().st_size / 1e6
        print(f"{minutes:>3} min: exit {os.waitstatus_to_exitcode(status)}, {r['sim_seconds']:.1f} s simulated, "
              f"wall {wall:.1f} s, {r['cycles'] / wall / 1e6:.1f} Mcycles/s, peak RSS {usage.ru_maxrss / 1024:.1f} MiB, "
              f"truth.csv {truth_mb:.1f} MB, verdict {r['verdict']}", flush=True)


if __name__ == "__main__":
    main()
