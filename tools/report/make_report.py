#!/usr/bin/python3
"""Plots a ddmr-hil run and writes report.md beside its artifacts.

Usage: make_report.py RUN_DIR

Reads RUN_DIR/summary.json, truth.csv, firmware.csv, eeprom_log.csv and, when
present, sim.csv and compare.json (written by `ddmr-hil compare`). Writes PNG
and SVG plots (X-Y trajectories, tracking error, wheel speeds, drive, motor
currents, battery voltage) and report.md, which embeds them with the key
numbers. Output is deterministic: the same run gives the same bytes.
"""
import csv
import json
import math
import os
import sys

from plot_common import plt, save as save_figure

# The reference sketch's goal circles: radius [m], period [s].
CASES = {1: (0.6, 12.0), 2: (0.4, 8.0)}


def read_csv(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) for r in rows] for k in (rows[0].keys() if rows else [])}


def fmt_int(v):
    return "n/a" if v is None else f"{v:.0f}"


def save(fig, run_dir, name):
    fig.tight_layout()
    save_figure(fig, run_dir, name)
    return name


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: make_report.py RUN_DIR\n")
        return 2
    run_dir = argv[1]
    try:
        with open(os.path.join(run_dir, "summary.json")) as f:
            summary = json.load(f)
        truth = read_csv(os.path.join(run_dir, "truth.csv"))
        fw = read_csv(os.path.join(run_dir, "firmware.csv"))
        log = read_csv(os.path.join(run_dir, "eeprom_log.csv"))
    except (OSError, ValueError, KeyError) as e:
        sys.stderr.write(f"make_report.py: error: {run_dir}: {e}\n")
        return 2
    sim_path = os.path.join(run_dir, "sim.csv")
    sim = read_csv(sim_path) if os.path.exists(sim_path) else None
    cmp_path = os.path.join(run_dir, "compare.json")
    compare = json.load(open(cmp_path)) if os.path.exists(cmp_path) else None

    case = summary.get("case", 1)
    radius, period = CASES.get(case, (0.6, 12.0))
    ready_s = (summary.get("ready_cycle") or 0) / summary["board"]["clock_hz"]  # the board's clock
    t_case = [t - ready_s for t in truth["t_s"]]
    in_case = [i for i, t in enumerate(t_case) if 0.0 <= t <= period + 0.5]
    plots = []

    # X-Y trajectories.
    fig, ax = plt.subplots(figsize=(6.5, 7.3))
    a = [2 * math.pi * k / 360 for k in range(361)]
    ax.plot([radius * math.cos(x) for x in a], [radius * math.sin(x) for x in a], "k--", lw=1,
            label=f"goal circle ({radius} m, {period:g} s)")
    ax.plot([truth["x_m"][i] for i in in_case], [truth["y_m"][i] for i in in_case], lw=1.5,
            label="plant truth (HIL)")
    if log:
        ax.plot(log["x_m"], log["y_m"], "o", ms=3, label="firmware EEPROM log")
    if sim:
        ax.plot(sim["x_m"], sim["y_m"], "--", lw=1.2, label="host simulation")
    ax.plot([0], [0], "g^", ms=9, label="start")
    end = summary["end_pose_truth"]
    ax.plot([end["x_m"]], [end["y_m"]], "rs", ms=8, label="end (truth)")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"Case {case}: trajectories")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.09), ncol=3, fontsize=8)
    plots.append(save(fig, run_dir, "xy"))

    # Tracking error over time.
    w = 2 * math.pi / period
    err = []
    for i in in_case:
        tc = t_case[i]
        gx, gy = radius * math.cos(w * tc), radius * math.sin(w * tc)
        err.append(math.hypot(gx - truth["x_m"][i], gy - truth["y_m"][i]))
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot([t_case[i] for i in in_case], err, label="|goal - truth|")
    if fw:
        fw_t = [t - ready_s for t in fw["t_avr_s"]]
        ax.plot(fw_t, [math.hypot(x, y) for x, y in zip(fw["errx"], fw["erry"])], lw=1,
                label="|goal - firmware estimate| (errx, erry)")
    ax.set_xlabel("time since the case byte [s]")
    ax.set_ylabel("tracking error [m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    plots.append(save(fig, run_dir, "tracking_error"))

    def series(name, keys, labels, ylabel):
        fig, ax = plt.subplots(figsize=(8, 3.5))
        for k, lab in zip(keys, labels):
            ax.plot([t_case[i] for i in in_case], [truth[k][i] for i in in_case], lw=1, label=lab)
        ax.set_xlabel("time since the case byte [s]")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        plots.append(save(fig, run_dir, name))

    series("wheel_speeds", ["wheel1_rad_s", "wheel2_rad_s"], ["wheel 1 (right)", "wheel 2 (left)"],
           "wheel speed [rad/s]")
    series("drive", ["duty1", "duty2", "dir1", "dir2"],
           ["duty 1 (pin 10)", "duty 2 (pin 11)", "direction 1 (pin 12)", "direction 2 (pin 13)"],
           "duty [0-1], direction [1 = forward]")
    series("currents", ["ia1_A", "ia2_A"], ["motor 1", "motor 2"], "armature current [A]")
    series("battery", ["vbatt_V"], ["battery terminal voltage"], "voltage [V]")

    rep = summary.get("firmware_report", {})
    enc = summary.get("encoder", {})
    fwp = summary.get("end_pose_firmware") or {}
    lines = [
        f"# ddmr-hil run: case {case}",
        "",
        f"Firmware `{summary['firmware']['path']}` (sha256 `{summary['firmware']['sha256'][:16]}...`, "
        f"{summary['firmware']['flash_bytes']} bytes of flash). PWM model: {summary.get('pwm')}, "
        f"EEPROM timing: {summary.get('eeprom_timing')}.",
        "",
        "| quantity | value |",
        "| --- | --- |",
        f"| exit | {summary['exit_reason']} |",
        f"| simulated time | {summary['sim_seconds']:.3f} s ({summary['cycles_total']} cycles) |",
        f"| loop iterations, mean period | {summary.get('loop_iterations')}, "
        f"{summary.get('mean_loop_period_s', 0) * 1e3:.3f} ms |",
        f"| Count1 / Count2 (printed) | {fmt_int(rep.get('count1'))} / {fmt_int(rep.get('count2'))} |",
        f"| encoder edges injected / ISRs / lost, ch 1 | {enc.get('channel1', {}).get('edges_injected')} / "
        f"{enc.get('channel1', {}).get('isr_count')} / {enc.get('channel1', {}).get('lost_edges')} |",
        f"| encoder edges injected / ISRs / lost, ch 2 | {enc.get('channel2', {}).get('edges_injected')} / "
        f"{enc.get('channel2', {}).get('isr_count')} / {enc.get('channel2', {}).get('lost_edges')} |",
        f"| end pose, plant truth | ({end['x_m']:.4f}, {end['y_m']:.4f}) m, {end['theta_rad']:.4f} rad |",
        f"| end pose, firmware estimate | ({fwp.get('x_m', float('nan')):.4f}, {fwp.get('y_m', float('nan')):.4f}) m, "
        f"{fwp.get('theta_rad', float('nan')):.4f} rad |",
        f"| EEPROM log samples | {summary.get('eeprom_log_samples')} |",
        "",
    ]
    if compare:
        lines += ["## Comparison", "", "| pair | rms [m] | max [m] | endpoint [m] | endpoint [%] |",
                  "| --- | --- | --- | --- | --- |"]
        for name, p in compare.get("pairs", {}).items():
            lines.append(f"| {name} | {p['rms_m']:.4f} | {p['max_m']:.4f} | {p['endpoint_m']:.4f} | "
                         f"{p['endpoint_pct']:.2f} |")
        lines.append("")
        if compare.get("attribution"):
            lines += ["### Attribution (each fidelity switch alone, against the EEPROM log)", "",
                      "| switch | endpoint change [m] | rms change [m] |", "| --- | --- | --- |"]
            for row in compare["attribution"]:
                lines.append(f"| {row['switch']} | {row['endpoint_change_m']:+.4f} | {row['rms_change_m']:+.4f} |")
            lines.append("")
    lp = summary.get("loop_profile")
    if lp:
        lines += ["## Control-loop cycle counts", "",
                  "| iterations | part | count | min [us] | mean [us] | p99 [us] | max [us] |",
                  "| --- | --- | --- | --- | --- | --- | --- |"]
        for group in ("without_eeprom_write", "with_eeprom_write", "all"):
            for part in ("compute", "wait", "period"):
                d = lp[group][part]
                if d["count"] == 0:
                    continue
                lines.append(f"| {group.replace('_', ' ')} | {part} | {d['count']} | {d['min_us']:.1f} | "
                             f"{d['mean_us']:.1f} | {d['p99_us']:.1f} | {d['max_us']:.1f} |")
        lines.append("")
    isr_md = os.path.join(run_dir, "isr.md")
    if os.path.exists(isr_md):
        with open(isr_md) as f:
            lines += ["## ISR timing", "", f.read(), ""]
    titles = {"xy": "X-Y trajectories", "tracking_error": "Tracking error", "wheel_speeds": "Wheel speeds",
              "drive": "Drive (duty and direction)", "currents": "Motor currents", "battery": "Battery voltage"}
    for p in plots:
        lines += [f"## {titles[p]}", "", f"![{titles[p]}]({p}.png)", ""]
    tmp = os.path.join(run_dir, "report.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
    os.replace(tmp, os.path.join(run_dir, "report.md"))
    print(os.path.join(run_dir, "report.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
