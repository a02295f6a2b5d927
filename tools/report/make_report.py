#!/usr/bin/python3
"""Plots a ddmr-hil output folder and writes report.md beside its artifacts.

Usage: make_report.py DIR     (run by `ddmr-hil report DIR`)

DIR is told apart by its files, as `ddmr-hil report` does:
- a `run` or `profile` folder (summary.json with clock_hz): reads summary.json,
  truth.csv, firmware.csv, eeprom_log.csv and, when present, sim.csv and
  compare.json (written by `ddmr-hil compare`); plots X-Y trajectories,
  tracking error, wheel speeds, drive, motor currents, battery voltage;
- a `sim` folder (summary.json with model and fidelity): sim_report.py;
- a `scenario` folder (results.json) or one scenario's sub-folder
  (result.json): scenario_report.py.
Writes PNG and SVG plots and report.md, which embeds them, a caption under
each, with the key numbers. Output is deterministic: the same folder gives
the same bytes.
"""
import json
import math
import os
import sys

import scenario_report
import sim_report
from plot_common import (CAPTIONS, distance, finish_time_plot, finish_xy, goal_circle, isr_section,
                         not_available_section, plant_plots, plot_sections, plt, read_csv, read_csv_if_present,
                         write_markdown, xy_axes)

# The reference sketch's goal circles: radius [m], period [s].
CASES = {1: (0.6, 12.0), 2: (0.4, 8.0)}


def fmt_int(v):
    return "n/a" if v is None else f"{v:.0f}"


def folder_kind(folder):
    """run (also profile), sim, scenario (a suite: results.json), scenario_result
    (one scenario's sub-folder: result.json) or other; the same files
    `ddmr-hil report` tells apart (tools/common/output_folder.cpp)."""
    summary = os.path.join(folder, "summary.json")
    if os.path.isfile(summary):
        try:
            with open(summary) as f:
                j = json.load(f)
        except ValueError:
            return "other"
        if isinstance(j, dict) and "clock_hz" in j:
            return "run"
        if isinstance(j, dict) and "model" in j and "fidelity" in j:
            return "sim"
        return "other"
    if os.path.isfile(os.path.join(folder, "results.json")):
        return "scenario"
    if os.path.isfile(os.path.join(folder, "result.json")):
        return "scenario_result"
    return "other"


def run_report(run_dir):
    """Plots a run (or profile) folder and writes its report.md; returns [its path]."""
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    truth = read_csv(os.path.join(run_dir, "truth.csv"))
    fw = read_csv(os.path.join(run_dir, "firmware.csv"))
    log = read_csv(os.path.join(run_dir, "eeprom_log.csv"))
    sim = read_csv_if_present(os.path.join(run_dir, "sim.csv"))
    compare = None
    if os.path.exists(os.path.join(run_dir, "compare.json")):
        with open(os.path.join(run_dir, "compare.json")) as f:
            compare = json.load(f)

    case = summary.get("case", 1)
    radius, period = CASES.get(case, (0.6, 12.0))
    ready_s = (summary.get("ready_cycle") or 0) / summary["board"]["clock_hz"]  # the board's clock
    t_case = [t - ready_s for t in truth["t_s"]]
    in_case = [i for i, t in enumerate(t_case) if 0.0 <= t <= period + 0.5]
    t_in = [t_case[i] for i in in_case]
    x_in = [truth["x_m"][i] for i in in_case]
    y_in = [truth["y_m"][i] for i in in_case]
    xlabel = "time since the case byte [s]"
    plots = []

    # X-Y trajectories.
    fig, ax = xy_axes(run_dir)
    goal_circle(ax, radius, period)
    ax.plot(x_in, y_in, lw=1.5, label="plant truth (HIL)")
    if log:
        ax.plot(log["x_m"], log["y_m"], "o", ms=3, label="firmware EEPROM log")
    if sim:
        ax.plot(sim["x_m"], sim["y_m"], "--", lw=1.2, label="host simulation")
    ax.plot([0], [0], "g^", ms=9, label="start")
    end = summary["end_pose_truth"]
    ax.plot([end["x_m"]], [end["y_m"]], "rs", ms=8, label="end (truth)")
    plots.append(finish_xy(fig, ax, f"Case {case}: trajectories", run_dir))

    # Tracking error over time.
    w = 2 * math.pi / period
    err = distance(x_in, y_in, [radius * math.cos(w * t) for t in t_in], [radius * math.sin(w * t) for t in t_in])
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t_in, err, label="|goal - truth|")
    if fw:
        fw_t = [t - ready_s for t in fw["t_avr_s"]]
        ax.plot(fw_t, [math.hypot(x, y) for x, y in zip(fw["errx"], fw["erry"])], lw=1,
                label="|goal - firmware estimate| (errx, erry)")
    plots.append(finish_time_plot(fig, ax, xlabel, "tracking error [m]", run_dir, "tracking_error"))

    plant, missing = plant_plots(run_dir, truth, in_case, t_in, xlabel, "truth.csv",
                                 "the motors were not driven during the case")
    plots += plant

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
    lines += isr_section(run_dir)
    captions = dict(CAPTIONS)
    captions.update({
        "xy": "The goal circle, where the plant went (truth), what the firmware logged (its own odometry, "
              "every 10th iteration) and, after `ddmr-hil compare`, the host simulation. Look at the end points: "
              "the thesis's metric is the end error over the length of the end vector.",
        "tracking_error": "Two errors that differ on purpose: |goal - truth| is where the robot really is, "
                          "|goal - firmware estimate| is what the controller sees (its errx, erry). The "
                          "controller drives its own error to zero; the gap between the lines is the odometry's "
                          "drift (encoder quantisation, wheel radius and slip), which no feedback on it can see.",
    })
    lines += plot_sections(plots, captions) + not_available_section(missing)
    return [write_markdown(run_dir, lines)]


def main(argv):
    if len(argv) != 2:
        sys.stderr.write("usage: make_report.py DIR   (a run, profile, sim or scenario output folder)\n")
        return 2
    folder = argv[1]
    kind = folder_kind(folder)
    reports = {"run": run_report, "sim": sim_report.report, "scenario": scenario_report.suite_report,
               "scenario_result": scenario_report.scenario_report}
    if kind not in reports:
        what = "no such folder" if not os.path.isdir(folder) else "not a run, profile, sim or scenario output folder"
        sys.stderr.write(f"make_report.py: error: {folder}: {what}\n")
        return 2
    try:
        written = reports[kind](folder)
    except (OSError, ValueError, KeyError) as e:
        sys.stderr.write(f"make_report.py: error: {folder}: {e!r}\n")
        return 2
    for path in written:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
