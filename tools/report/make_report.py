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


# The Uno's 490 Hz phase-correct PWM: 1 / 490.2 s. Currents and the battery
# voltage follow each PWM pulse; sampled at 1 kHz (truth.csv) they alias into
# solid blocks. Plotted instead: the mean over windows of whole PWM periods,
# and the envelope (min and max) of each window. The window is 25 periods
# (51.0 ms): 1 kHz against 490.196 Hz beats at |1000 - 2 x 490.196| = 19.61 Hz,
# one beat every 51.0 ms, so a window's 51 samples fall at evenly spread
# phases of the PWM cycle and their mean is the cycle's mean.
PWM_PERIOD_S = 510.0 * 64 / 16e6  # Timer1/2 phase-correct 8-bit (TOP 255: 510 counts), prescaler 64
WINDOW_PERIODS = 25


def window_stats(t, y, window_s):
    """Consecutive windows of window_s [s] from t[0]: (centre time, mean, min,
    max) of the samples in each; a last partial window is dropped."""
    out = []
    if not t:
        return out
    start, i, n = t[0], 0, len(t)
    while True:
        end = start + window_s
        j = i
        while j < n and t[j] < end:
            j += 1
        if j >= n:  # partial window at the end
            break
        if j > i:
            chunk = y[i:j]
            out.append((start + window_s / 2, sum(chunk) / len(chunk), min(chunk), max(chunk)))
        i, start = j, end
    return out


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
    def pwm_series(name, keys, labels, ylabel):
        """Mean per window of WINDOW_PERIODS PWM periods, with the envelope."""
        fig, ax = plt.subplots(figsize=(8, 3.5))
        window_s = WINDOW_PERIODS * PWM_PERIOD_S
        for n, (k, lab) in enumerate(zip(keys, labels)):
            st = window_stats([t_case[i] for i in in_case], [truth[k][i] for i in in_case], window_s)
            tc = [w[0] for w in st]
            colour = f"C{n}"
            ax.fill_between(tc, [w[2] for w in st], [w[3] for w in st], color=colour, alpha=0.15, lw=0,
                            label=f"{lab}: min-max per window")
            ax.plot(tc, [w[1] for w in st], color=colour, lw=1.6, ls="-" if n == 0 else "--",
                    label=f"{lab}: mean over {WINDOW_PERIODS} PWM periods ({window_s * 1e3:.1f} ms)")
        ax.set_xlabel("time since the case byte [s]")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        plots.append(save(fig, run_dir, name))

    pwm_series("currents", ["ia1_A", "ia2_A"], ["motor 1 (right)", "motor 2 (left)"], "armature current [A]")
    pwm_series("battery", ["vbatt_V"], ["battery terminal voltage"], "voltage [V]")

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
    captions = {
        "xy": "The goal circle, where the plant went (truth), what the firmware logged (its own odometry, "
              "every 10th iteration) and, after `ddmr-hil compare`, the host simulation. Look at the end points: "
              "the thesis's metric is the end error over the length of the end vector.",
        "tracking_error": "Two errors that differ on purpose: |goal - truth| is where the robot really is, "
                          "|goal - firmware estimate| is what the controller sees (its errx, erry). The "
                          "controller drives its own error to zero; the gap between the lines is the odometry's "
                          "drift (encoder quantisation, wheel radius and slip), which no feedback on it can see.",
        "wheel_speeds": "The wheels' speeds from the plant: the outer (right) wheel turns faster on the circle.",
        "drive": "What the L298 is told, per coupling step: duty (mean enable level) and direction.",
        "currents": f"The motor currents, averaged over {WINDOW_PERIODS} PWM periods "
                    f"({WINDOW_PERIODS * PWM_PERIOD_S * 1e3:.1f} ms), with their range in each window shaded: the "
                    "current rises and falls with every 490 Hz pulse, so 1 kHz samples of it alias into blocks. "
                    "Look at the means for the load, at the band for the ripple.",
        "battery": "The battery's terminal voltage, averaged the same way: it dips with each pulse's current "
                   "(internal resistance) and sags slowly with the charge drawn.",
    }
    for p in plots:
        lines += [f"## {titles[p]}", "", f"![{titles[p]}]({p}.png)", "", f"*{captions[p]}*", ""]
    tmp = os.path.join(run_dir, "report.md.tmp")
    with open(tmp, "w") as f:
        f.write("\n".join(lines))
    os.replace(tmp, os.path.join(run_dir, "report.md"))
    print(os.path.join(run_dir, "report.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
