#!/usr/bin/env python3
"""Collects `make bench`'s Google Benchmark results into one table.

Reads BENCH_DIR/{hil,sim,plant,calibrate,world}.json (written by ddmr_hil_bench,
ddmr_sim_bench, ddmr_plant_bench, ddmr_calibrate_bench and ddmr_world_bench),
python.json (tools/python/bench/bench_api.py) and monte_carlo.json
(tools/python/examples/monte_carlo_circle.py), writes BENCH_DIR/results.json and prints a table: per
benchmark the median and the spread (min..max over the repetitions) of its
figure, then the ratios against the goals of issues 4, 6, 7, 8, 18, 33 and 34. The
machine is shared and noisy: the ratios of figures measured in the same run
are the ones to trust.

Usage: bench_table.py BENCH_DIR
"""
import json
import statistics
import sys
from pathlib import Path


# Google Benchmark's own keys of a run; every other number in it is one of
# our state.counters (peak_rss_MiB, rms_mm, truth_in_interval, ...), kept
# whatever its name: a counter the table does not know is still in
# results.json, and a goal reads it by name.
BENCHMARK_FIELDS = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
    "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name",
    "aggregate_unit", "label", "error_occurred", "error_message", "skipped", "skip_message",
    "Mcycles_per_s", "runs_per_minute",  # the figure of the row (its "values")
}
# Counters where more is better: over repetitions the table keeps the least
# (the worst), as it keeps the most of the others (RSS, error, evaluations).
LARGER_IS_BETTER = {"truth_in_interval"}


def load(path):
    """{run_name: {"values": [...], "unit": str, "counters": {...}}} from one JSON file."""
    if not path.exists():
        return {}
    data = json.loads(path.read_text())
    out = {}
    for b in data.get("benchmarks", []):
        if b.get("run_type") == "aggregate":
            continue
        name = b.get("run_name", b["name"])
        for key, unit in (("Mcycles_per_s", "Mcycles/s"), ("runs_per_minute", "runs/min")):
            if key in b:
                value = b[key]
                break
        else:
            value = b["real_time"]
            unit = b["time_unit"]
        entry = out.setdefault(name, {"values": [], "unit": unit, "counters": {}, "times": []})
        entry["values"].append(value)
        scale = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}[b["time_unit"]]
        entry["times"].append(b["real_time"] * scale)
        for k, v in b.items():
            if k in BENCHMARK_FIELDS or isinstance(v, bool) or not isinstance(v, (int, float)):
                continue
            worst = min if k in LARGER_IS_BETTER else max
            entry["counters"][k] = worst(entry["counters"][k], v) if k in entry["counters"] else v
    return out


def main():
    bench = Path(sys.argv[1] if len(sys.argv) > 1 else "build/bench")
    runs = {}
    for f in ("hil.json", "sim.json", "plant.json", "calibrate.json", "world.json"):
        runs.update(load(bench / f))
    rows = {}
    for name, e in runs.items():
        v = e["values"]
        rows[name] = {"median": statistics.median(v), "min": min(v), "max": max(v), "n": len(v), "unit": e["unit"],
                      "median_wall_s": statistics.median(e["times"]), **e["counters"]}

    def med(name):
        return rows[name]["median"] if name in rows else None

    short = lambda n: n.replace("/iterations:1", "").replace("/repeats:3", "").replace("/real_time", "").replace("/manual_time", "")
    print(f"{'benchmark':<46} {'median':>12} {'min..max':>21} {'unit':<10} n")
    for name in sorted(rows):
        r = rows[name]
        extra = f"  peak RSS {r['peak_rss_MiB']:.1f} MiB" if "peak_rss_MiB" in r else ""
        print(f"{short(name):<46} {r['median']:>12.2f} {r['min']:>10.2f}..{r['max']:<10.2f} {r['unit']:<10} {r['n']}{extra}")

    def find(prefix):
        for n in rows:
            if n.startswith(prefix):
                return n
        return None

    bare, hil = med(find("BM_BareSimavrDefaultLoop")), med(find("BM_FullHilCase1"))
    run, prof, vcd = med(find("BM_RunCase1/")), med(find("BM_RunCase1Profile")), med(find("BM_RunCase1Vcd"))
    j1, j2 = med(find("BM_ScenarioThroughput/1")), med(find("BM_ScenarioThroughput/2"))
    long1, long10 = find("BM_LongRun/1/"), find("BM_LongRun/10/")
    suite = med(find("BM_ShippedScenarioSuite"))
    sim_ideal, sim_fw = med(find("BM_SimCase1Ideal/")) or med("BM_SimCase1Ideal"), med("BM_SimCase1Firmware")
    goals = []

    def goal(what, value, target, ok):
        goals.append({"goal": what, "value": value, "target": target, "met": bool(ok)})

    if bare and hil:
        goal("full HIL / bare simavr default loop", hil / bare, ">= 1.5", hil / bare >= 1.5)
    if run and hil:
        goal("run with profiling, VCD and gdb off / bare rig (their cost when off)", run / hil, "~1 (nothing measurable)", run / hil >= 0.9)
    # Issue 32: the engine with every optional instrument off, and each instrument's own cost.
    run_none = med(find("BM_RunCase1NoInstruments"))
    if run_none and hil:
        goal("run with the ISR monitor, stack guard and race detector off / bare rig", run_none / hil, ">= 0.95",
             run_none / hil >= 0.95)
    for label, bench_name in (("ISR monitor", "BM_RunCase1IsrMonitorOnly"), ("stack guard", "BM_RunCase1StackGuardOnly"),
                              ("race detector", "BM_RunCase1RaceDetectorOnly")):
        alone = med(find(bench_name))
        if alone and run_none:
            goal(f"run with only the {label} on / with none (its cost)", alone / run_none, "reported", True)
    if prof and bare:
        goal("profiling on / bare simavr", prof / bare, ">= 0.3", prof / bare >= 0.3)
        goal("profiling on, real-time factor", prof / 16.0, "several x real time", prof / 16.0 >= 2.0)
    if vcd and run:
        goal("--vcd / run", vcd / run, "~1", vcd / run >= 0.8)
    if run:
        wall = rows[find("BM_RunCase1/")]["median_wall_s"]  # boot to the end of the report, artifacts written
        goal("case 1 boot to END (ddmr-hil run), wall seconds", wall, "< 3 s", wall < 3.0)
    # Issue 3: a plant step against the time bare simavr spends on the cycles it covers.
    step1000, plant12 = med("BM_PlantStepSwitched/1000"), med("BM_Plant12sSwitched")
    if bare and step1000:
        simavr_ns = 1000 / bare * 1000.0  # 1000 cycles at `bare` Mcycles/s, in ns
        goal("plant step of 1000 cycles (switched) / bare simavr's time for them", step1000 / simavr_ns, "< 0.01", step1000 / simavr_ns < 0.01)
    if bare and plant12:
        simavr_ms = 12 * 16e6 / (bare * 1e6) * 1000.0
        goal("12 s of plant as the HIL drives it / bare simavr's time for 12 s", plant12 / simavr_ms, "< 0.01", plant12 / simavr_ms < 0.01)
    if sim_ideal is not None:
        goal("host simulation of 12 s (ideal), ms", sim_ideal, "< 50 ms", sim_ideal < 50.0)
    if sim_fw is not None:
        goal("host simulation of 12 s (firmware model), ms", sim_fw, "< 50 ms", sim_fw < 50.0)
    if j1 and j2:
        goal("16 case-1 runs: 2 workers / 1 worker", j2 / j1, ">= 1.8", j2 / j1 >= 1.8)
    if suite is not None:
        goal("shipped scenario suite, wall seconds", suite, "< 120 s", suite < 120.0)
    # Issue 18: five parameters on two logs, under 2 minutes, and right.
    name = find("BM_Calibrate5Params2Logs")
    if name:
        r = rows[name]
        goal("calibration of 5 parameters on 2 logs, wall seconds", r["median_wall_s"], "< 120 s", r["median_wall_s"] < 120.0)
        goal("calibration: RMS distance of the fitted plant to the logs, mm", r.get("rms_mm", 1e9), "< 5", r.get("rms_mm", 1e9) < 5.0)
        goal("calibration: true values inside their intervals (of 5)", r.get("truth_in_interval", 0), "5",
             r.get("truth_in_interval", 0) == 5)
    # Issue 33: five sensors among 50 walls against 0 walls.
    name = find("BM_WorldWallsCost")
    if name and "ratio_50_to_0" in rows[name]:
        ratio = rows[name]["ratio_50_to_0"]
        goal("5 sensors, 50 walls / 0 walls (wall time)", ratio, "<= 1.10", ratio <= 1.10)
    # Issue 34: tools/python/bench/bench_api.py and the Monte-Carlo example
    # write plain JSON, not Google Benchmark's.
    python = json.loads((bench / "python.json").read_text()) if (bench / "python.json").exists() else None
    if python:
        c, w = python["case1"], python["sweep"]
        goal("case 1 driven from Python / ddmr-hil run (wall)", c["ratio"], "<= 1.05", c["ratio"] <= 1.05)
        goal(f"Dask sweep of {w['plants']} plants: 1 worker / 2 workers", w["speedup"], ">= 1.7", w["speedup"] >= 1.7)
    # Issue 35: tools/python/bench/bench_fast_forward.py (plain JSON too).
    ff = json.loads((bench / "fast_forward.json").read_text()) if (bench / "fast_forward.json").exists() else None
    if ff:
        c, s = ff["case1"], ff["suite"]
        goal("case 1: --no-fast-forward / fast-forward (wall)", c["ratio"], ">= 3", c["ratio"] >= 3.0)
        goal("case 1: share of cycles skipped", c["skipped_share"], ">= 0.70", c["skipped_share"] >= 0.70)
        goal(f"{s['scenarios']} scenarios: --no-fast-forward / fast-forward (wall)", s["ratio"], ">= 2.5",
             s["ratio"] >= 2.5)
    mc = json.loads((bench / "monte_carlo.json").read_text()) if (bench / "monte_carlo.json").exists() else None
    if mc:
        goal(f"Monte Carlo: fraction of {mc['plants']} plants within {mc['miss_limit_m'] * 100:.0f} cm of the goal",
             mc["fraction_within"], "reported", True)
    if long1 and long10:
        a, b = rows[long1], rows[long10]
        goal("10-min / 1-min simulated run: Mcycles/s", b["median"] / a["median"], "~1 (linear cost)", b["median"] / a["median"] >= 0.9)
        goal("10-min / 1-min simulated run: peak RSS", b.get("peak_rss_MiB", 0) / max(a.get("peak_rss_MiB", 1), 1e-9),
             "~1 (flat memory)", b.get("peak_rss_MiB", 0) <= 1.1 * a.get("peak_rss_MiB", 0))
    print()
    for g in goals:
        print(f"{'met ' if g['met'] else 'MISS'} {g['goal']:<66} {g['value']:>9.3f}  (goal {g['target']})")
    (bench / "results.json").write_text(json.dumps({"benchmarks": rows, "goals": goals}, indent=2) + "\n")
    print(f"\nwrote {bench / 'results.json'}")


if __name__ == "__main__":
    main()
