"""The reports of a `ddmr-hil scenario` folder (make_report.py DIR).

A suite folder (results.json) gets one report per scenario sub-folder and an
index report.md: each scenario's verdict, message and a link to its report.
One scenario's sub-folder (result.json) gets its own: the plant's truth
trajectory (truth.csv) with the firmware's EEPROM log and the expect-pose
targets, the wheel speeds, drive, and the currents and battery voltage as
PWM-window means against AVR time with each step's time marked (red where a
step failed), the steps with their verdicts, the end of uart.txt, isr.md.
What the folder lacks (a crash before the plant ran leaves truth.csv empty)
is listed under "Not available".
"""
import json
import os
import re

from plot_common import (CAPTIONS, finish_xy, isr_section, not_available_section, plant_plots, plot_sections,
                         read_csv_if_present, step_marks, write_markdown, xy_axes)
from matplotlib.patches import Circle  # after plot_common: it says what to install if matplotlib is missing

XLABEL = "AVR time [s]"
UART_TAIL_LINES = 12

_POSE_KEY = re.compile(r"\b(source|x_m|y_m|tol_m):\s*([^,}\s]+)")


def pose_targets(steps):
    """The expect-pose steps of result.json as (source, x_m, y_m, tol_m,
    passed), read from each step's text ({expect-pose: {x_m: ..., ...}}); the
    source defaults to truth, tol_m to 0 if the text lacks it."""
    out = []
    for st in steps:
        if st["kind"] != "expect-pose":
            continue
        kv = dict(_POSE_KEY.findall(st["step"]))
        try:
            out.append((kv.get("source", "truth"), float(kv["x_m"]), float(kv["y_m"]), float(kv.get("tol_m", 0)),
                        st["passed"]))
        except (KeyError, ValueError):
            continue  # a step text this version cannot read: no target drawn
    return out


def md_cell(text):
    """text made safe for one markdown table cell."""
    return str(text).replace("|", "&#124;").replace("\n", " ")


def verdict_word(v):
    return {"pass": "PASS", "fail": "FAIL"}.get(v, "ERROR")


def uart_tail(folder):
    path = os.path.join(folder, "uart.txt")
    if not os.path.exists(path):
        return []
    with open(path, errors="replace") as f:
        text = f.read()
    tail = text.splitlines()[-UART_TAIL_LINES:]
    if not tail:
        return ["## UART", "", "The firmware sent nothing (uart.txt is empty).", ""]
    return ([f"## UART (the last {len(tail)} lines of uart.txt)", "", "```"] + tail + ["```", ""])


def result_lines(r):
    """report.md's heading, result table and step table of a result.json."""
    lines = [
        f"# ddmr-hil scenario: {r['name']} ({verdict_word(r['verdict'])})",
        "",
        "| quantity | value |",
        "| --- | --- |",
        f"| scenario file | `{r['file']}` |",
        f"| firmware | `{r['firmware']}` |",
        f"| board | {'`' + r['board'] + '`' if r.get('board') else 'the thesis robot (default)'} |",
        f"| verdict, exit code | {r['verdict']}, {r['exit_code']} |",
    ]
    if r.get("message"):
        lines.append(f"| message | {md_cell(r['message'])} |")
    lines += [
        f"| simulated time | {r['sim_seconds']:.3f} s ({r['cycles']} cycles at {r['clock_hz'] / 1e6:g} MHz) |",
        f"| seed, baud | {r['seed']}, {r['baud']} |",
        f"| UART bytes, framing errors | {r['uart_bytes']}, {r['framing_errors']} |",
        f"| steps run | {len(r['steps'])} of {r['steps_total']} |",
        "",
    ]
    for w in r.get("wiring_warnings") or []:
        lines.append(f"- wiring warning: {w}")
    if r.get("wiring_warnings"):
        lines.append("")
    lines += ["## Steps", "", "| line | step | ended at [s] | verdict | message |", "| --- | --- | --- | --- | --- |"]
    for st in r["steps"]:
        lines.append(f"| {st['line']} | `{md_cell(st['step'])}` | {st['t_s']:.6f} | "
                     f"{'ok' if st['passed'] else '**FAILED**'} | {md_cell(st['message'])} |")
    if len(r["steps"]) < r["steps_total"]:
        lines.append(f"| | {r['steps_total'] - len(r['steps'])} more step(s) not run | | | |")
    lines.append("")
    return lines


def scenario_report(folder):
    """Plots one scenario's sub-folder and writes its report.md; returns [its path]."""
    with open(os.path.join(folder, "result.json")) as f:
        r = json.load(f)
    truth = read_csv_if_present(os.path.join(folder, "truth.csv"))
    log = read_csv_if_present(os.path.join(folder, "eeprom_log.csv"))
    marks = step_marks(r["steps"])
    plots, missing = [], []
    if not truth:
        missing.append("every plot: truth.csv is missing or has no rows (the run stopped before the plant "
                       "was coupled)")
    else:
        t = truth["t_s"]
        fig, ax = xy_axes(folder)
        ax.plot(truth["x_m"], truth["y_m"], lw=1.5, label="plant truth")
        if log:
            ax.plot(log["x_m"], log["y_m"], "o", ms=3, label="firmware EEPROM log")
        else:
            missing.append("EEPROM log points on the X-Y plot: eeprom_log.csv has no samples")
        for source, x, y, tol, passed in pose_targets(r["steps"]):
            colour = "tab:green" if passed else "red"
            ax.add_patch(Circle((x, y), tol, fill=False, ls="--", lw=1, color=colour))
            ax.plot([x], [y], "+" if source == "truth" else "x", color=colour, ms=10,
                    label=f"expect-pose ({source}) ± {tol:g} m: {'ok' if passed else 'FAILED'}")
        ax.plot([truth["x_m"][0]], [truth["y_m"][0]], "g^", ms=9, label="start")
        ax.plot([truth["x_m"][-1]], [truth["y_m"][-1]], "rs", ms=8, label="end (truth)")
        plots.append(finish_xy(fig, ax, f"Scenario {r['name']}: trajectory", folder))
        missing.append("Tracking error: a scenario has no goal trajectory (its firmware has its own)")
        plant, plant_missing = plant_plots(folder, truth, range(len(t)), t, XLABEL, "truth.csv",
                                             "the firmware never drove the motors in this scenario", marks)
        plots += plant
        missing += plant_missing
    lines = result_lines(r) + uart_tail(folder) + isr_section(folder)
    marks_note = (" The dotted lines are the steps' end times, labelled with their YAML lines; red where a step "
                  "failed.")
    captions = {k: v + marks_note for k, v in CAPTIONS.items()}
    captions["xy"] = ("Where the plant went (truth), what the firmware logged (its odometry, when it logs in "
                      "the reference format) and each expect-pose target with its tolerance circle (+ truth, "
                      "x firmware; green passed, red failed). A push step shows as a jump.")
    lines += plot_sections(plots, captions) + not_available_section(missing)
    if os.path.exists(os.path.join(folder, "failure_window.vcd")):
        lines += ["`failure_window.vcd`: the last 0.5 s of AVR time before the end (pins, PWM, ISRs); "
                  "GTKWave opens it.", ""]
    return [write_markdown(folder, lines)]


def suite_lines(results, reports):
    """The index report.md of a suite: the counts, then per scenario its
    verdict, simulated time, message and its report's link (or why there is none)."""
    lines = [
        f"# ddmr-hil scenarios: {results['passed']} of {results['total']} passed",
        "",
        f"{results['failed']} failed a check, {results['errors']} ended in an error (a firmware crash, a plant "
        "failure or a timeout).",
        "",
        "| scenario | verdict | simulated [s] | message | report |",
        "| --- | --- | --- | --- | --- |",
    ]
    for sc in results["scenarios"]:
        link = reports.get(sc["name"])
        cell = f"[{sc['name']}/report.md]({sc['name']}/report.md)" if link else "no result.json in its folder"
        lines.append(f"| {sc['name']} | {verdict_word(sc['verdict'])} | {sc['sim_seconds']:.3f} | "
                     f"{md_cell(sc['message'])} | {cell} |")
    lines.append("")
    return lines


def suite_report(folder):
    """One report per scenario sub-folder, then the index; returns their paths."""
    with open(os.path.join(folder, "results.json")) as f:
        results = json.load(f)
    written, reports = [], {}
    for sc in results["scenarios"]:
        sub = os.path.join(folder, sc["name"])
        if os.path.isfile(os.path.join(sub, "result.json")):
            reports[sc["name"]] = scenario_report(sub)[0]
            written.append(reports[sc["name"]])
    written.append(write_markdown(folder, suite_lines(results, reports)))
    return written
