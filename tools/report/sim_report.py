"""The report of a `ddmr-hil sim` folder (make_report.py SIM_DIR).

Reads summary.json (model, fidelity, case, gains, end pose, ...), sim.csv
(1 kHz: the pose, the goal, the plant's columns, the Lyapunov function) and,
when the run logged one, eeprom_log.csv. Plots the simulated trajectory
against the goal's, the tracking error |G - P|, the Lyapunov function, and
the plant's wheel speeds, drive, currents and battery voltage where sim.csv
has them (the kinematic plant has no currents and a fixed battery); writes
report.md with the key numbers of summary.json (not its wall time, so the same
folder gives the same bytes).
"""
import json
import math
import os

from plot_common import (CAPTIONS, TITLES, distance, finish_xy, not_available_section, plant_plots, plot_sections,
                         read_csv, read_csv_if_present, time_series, varies, write_markdown, xy_axes)

XLABEL = "time [s]"


def case_text(case):
    """The case of summary.json in words: 'case1: circle R = 0.6 m, T = 12 s'."""
    if case.get("kind") == "circle":
        period = 2 * math.pi / case["rate_rad_s"] if case.get("rate_rad_s") else float("inf")
        return f"{case['name']}: circle R = {case['radius_m']:g} m, T = {period:.4g} s"
    return (f"{case['name']}: line at {case.get('line_speed_m_s'):g} m/s, {case.get('step_m'):g} m step in "
            f"{case.get('step_axis')} at {case.get('step_time_s'):g} s")


def gains_text(g):
    return (f"K_x {g['kx']:g}, K_y {g['ky']:g}, K_w {g['kw']:g}, v_ref {g['vref_m_s']:g} m/s, "
            f"w_ref {g['wref_rad_s']:g} rad/s")


def pose_text(p):
    theta = f", {p['theta_rad']:.4f} rad" if "theta_rad" in p else ""
    return f"({p['x_m']:.4f}, {p['y_m']:.4f}) m{theta}"


def summary_lines(s):
    """report.md's heading and table of summary.json's key numbers."""
    fidelity = ", ".join(s["fidelity"]) or "none (the thesis's idealisation)"
    log = s.get("eeprom_log", {})
    status = s.get("status")
    if "status_at_s" in s:
        status = f"{status} at t = {s['status_at_s']:.4f} s"
    return [
        f"# ddmr-hil sim: {s['case']['name']}, {s['model']} model",
        "",
        "| quantity | value |",
        "| --- | --- |",
        f"| model, fidelity switches | {s['model']}; {fidelity} |",
        f"| case | {case_text(s['case'])} |",
        f"| gains (as given) | {gains_text(s['gains'])} |",
        f"| gains (effective) | {gains_text(s['gains_effective'])} |",
        f"| plant, PWM | {s['plant']}; {s['pwm']} |",
        f"| duration, control period, plant step | {s['duration_s']:g} s, {s['period_s'] * 1e3:g} ms, "
        f"{s['plant_step_s']:g} s |",
        f"| end time (true, controller's clock) | {s['end_time_s']:.4f} s, {s['controller_end_time_s']:.4f} s |",
        f"| control iterations, plant steps | {s['control_iterations']}, {s['plant_steps']} |",
        f"| end pose (plant) | {pose_text(s['end_pose'])} |",
        f"| end pose (controller's estimate) | {pose_text(s['end_estimate'])} |",
        f"| goal at the end | {pose_text(s['goal_end'])} |",
        f"| end error &#124;G - P&#124; | {s['end_error_m']:.4f} m |",
        f"| EEPROM log | {'written' if log.get('written') else 'not written'}, {log.get('samples', 0)} samples"
        f"{', quantised' if log.get('quantised') else ''}{', truncated' if log.get('truncated') else ''} |",
        f"| plant status | {status} |",
        "",
    ]


def report(sim_dir):
    """Plots a sim folder and writes its report.md; returns [its path]."""
    with open(os.path.join(sim_dir, "summary.json")) as f:
        s = json.load(f)
    sim = read_csv(os.path.join(sim_dir, "sim.csv"))
    log = read_csv_if_present(os.path.join(sim_dir, "eeprom_log.csv"))
    lines = summary_lines(s)
    plots, missing = [], []
    if not sim:
        missing.append("every plot: sim.csv has no rows")
    else:
        t = sim["t_s"]
        fig, ax = xy_axes()
        ax.plot(sim["goal_x_m"], sim["goal_y_m"], "k--", lw=1, label=f"goal ({case_text(s['case'])})")
        ax.plot(sim["x_m"], sim["y_m"], lw=1.5, label=f"simulated robot ({s['model']} model)")
        if log:
            ax.plot(log["x_m"], log["y_m"], "o", ms=3, label="its EEPROM log (odometry)")
        ax.plot([sim["x_m"][0]], [sim["y_m"][0]], "g^", ms=9, label="start")
        ax.plot([s["end_pose"]["x_m"]], [s["end_pose"]["y_m"]], "rs", ms=8, label="end")
        ax.plot([s["goal_end"]["x_m"]], [s["goal_end"]["y_m"]], "kx", ms=9, label="goal at the end")
        plots.append(finish_xy(fig, ax, f"Host simulation, {s['case']['name']}: trajectories", sim_dir))
        if log is None:
            missing.append("EEPROM log points on the X-Y plot: this run wrote no log (no eeprom_log.csv)")

        err = distance(sim["x_m"], sim["y_m"], sim["goal_x_m"], sim["goal_y_m"])
        plots.append(time_series(sim_dir, "tracking_error", t, [(err, "|goal - robot|")], XLABEL,
                                 "tracking error [m]"))
        if "lyapunov" in sim and varies(sim["lyapunov"]):
            plots.append(time_series(sim_dir, "lyapunov", t, [(sim["lyapunov"], "V (eq. 15)")], XLABEL,
                                     "Lyapunov function V [m^2]"))
        else:
            missing.append("Lyapunov function: sim.csv's lyapunov column is missing, nan or constant "
                           "(eq. 15 is undefined with K_y = 0)")
        plant, plant_missing = plant_plots(sim_dir, sim, range(len(t)), t, XLABEL, "sim.csv",
                                             "the kinematic plant has no motors and a fixed battery")
        plots += plant
        missing += plant_missing
    titles = dict(TITLES, lyapunov="Lyapunov function")
    captions = dict(CAPTIONS)
    captions.update({
        "xy": "The goal's path (dashed), where the simulated robot went and, when the firmware model logs, "
              "its EEPROM log (the controller's odometry, every 10th iteration). Look at the end point against "
              "the goal's end (x): the end error is in the table.",
        "tracking_error": "|G - P|, the distance from the robot to where the goal is at the same moment. With "
                          "the sketch's feed-forward (v_ref = w_ref = 0.2, not the goal's speed) it settles to a "
                          "constant instead of 0 (docs/hostsim.md).",
        "lyapunov": "Eq. (15) of the true pose against the goal: with the kinematic plant and a feed-forward "
                    "that matches the goal it never rises; where it rises, the motors lag or the feed-forward "
                    "is off.",
        "currents": CAPTIONS["currents"].replace("1 kHz samples of it alias into blocks",
                                                 "with `--pwm switched` 1 kHz samples of it alias into blocks "
                                                 "(with `--pwm averaged` the band is narrow)"),
    })
    lines += plot_sections(plots, captions, titles) + not_available_section(missing)
    return [write_markdown(sim_dir, lines)]
