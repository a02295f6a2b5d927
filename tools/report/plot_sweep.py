#!/usr/bin/python3
"""Plots a `ddmr-hil sweep` folder as the thesis's figures 5-2 to 5-8 do.

Usage: plot_sweep.py SWEEP_DIR      (run by `ddmr-hil sweep` itself)
       plot_sweep.py --check        (exit 0 if matplotlib imports, else 2)

Reads SWEEP_DIR/sweep.json and each study's SWEEP_DIR/<id>.csv; writes
SWEEP_DIR/<id>.png and .svg, one figure per study, four panels, one curve
per gain value (per circle in fig5_8):
  (a) circles: the X-Y paths with the goal's (dashed), equal aspect;
      the line step: the robot-frame error along the step's axis
      (x_e for the step in X, y_e for Y; eq. 12), against time;
  (b) the tracking error |G - P| against time, with the settling band;
  (c) the forward velocity v_R and (d) the rotational velocity w_R against
      time (what A2's pages and fig. 5-2's left panel plot).
Deterministic: the same folder gives the same bytes (fixed SVG ids, no date).
"""
import csv
import json
import os
import sys

from plot_common import plt, save as save_figure

GAIN_LABEL = {"kx": "$K_x$", "ky": "$K_y$", "kw": "$K_w$"}
FLOAT_COLUMNS = ("t_s", "x_m", "y_m", "theta_rad", "goal_x_m", "goal_y_m", "error_m", "xe_m", "ye_m",
                 "v_m_s", "omega_rad_s")


def read_runs(path):
    """{(case, gain_value): {column: [floats]}}, in file order."""
    runs = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["case"], row["gain_value"])
            cols = runs.setdefault(key, {k: [] for k in FLOAT_COLUMNS})
            for k in FLOAT_COLUMNS:
                cols[k].append(float(row[k]))
    return runs


def case_label(traj):
    if traj["kind"] == "circle":
        return f"R = {traj['radius_m']:g} m, T = {traj['duration_s']:g} s"
    return f"20 cm step in {traj['step_axis'].upper()}"


def run_label(study, case, gain_value, trajectories):
    if study["varied"] == "none":
        return case_label(trajectories[case])
    return f"{GAIN_LABEL[study['varied']]} = {gain_value}"


def plot_study(out_dir, sweep, study):
    runs = read_runs(os.path.join(out_dir, study["csv"]))
    trajectories = {t["name"]: t for t in study["trajectories"]}
    line = all(t["kind"] == "line_step" for t in study["trajectories"])
    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    (ax_a, ax_b), (ax_c, ax_d) = axes

    for (case, gain_value), r in runs.items():
        label = run_label(study, case, gain_value, trajectories)
        if line:
            axis = trajectories[case]["step_axis"]
            ax_a.plot(r["t_s"], r["xe_m" if axis == "x" else "ye_m"], label=label)
        else:
            (path,) = ax_a.plot(r["x_m"], r["y_m"], label=label)
            if study["varied"] == "none":
                ax_a.plot(r["goal_x_m"], r["goal_y_m"], "--", color=path.get_color(), linewidth=0.8)
        ax_b.plot(r["t_s"], r["error_m"], label=label)
        ax_c.plot(r["t_s"], r["v_m_s"], label=label)
        ax_d.plot(r["t_s"], r["omega_rad_s"], label=label)

    if line:
        axis = study["trajectories"][0]["step_axis"]
        name = "x_e" if axis == "x" else "y_e"
        ax_a.set_title(f"(a) {axis.upper()} error in the robot frame, ${name}$ (eq. 12)")
        ax_a.set_xlabel("t [s]")
        ax_a.set_ylabel(f"${name}$ [m]")
    else:
        if study["varied"] != "none":  # one goal circle for every run
            first = next(iter(runs.values()))
            ax_a.plot(first["goal_x_m"], first["goal_y_m"], "k--", linewidth=0.8, label="goal")
        ax_a.set_title("(a) Tracking: robot paths (goal dashed)")
        ax_a.set_xlabel("X [m]")
        ax_a.set_ylabel("Y [m]")
        ax_a.set_aspect("equal", adjustable="datalim")
    band = sweep["settle_band_m"]
    ax_b.axhline(band, color="0.6", linewidth=0.8, linestyle=":", label=f"{band * 100:g} cm band")
    ax_b.set_title("(b) Tracking error |G - P|")
    ax_b.set_xlabel("t [s]")
    ax_b.set_ylabel("error [m]")
    ax_c.set_title("(c) Forward velocity $v_R$")
    ax_c.set_xlabel("t [s]")
    ax_c.set_ylabel("$v_R$ [m/s]")
    ax_d.set_title(r"(d) Rotational velocity $\omega_R$")
    ax_d.set_xlabel("t [s]")
    ax_d.set_ylabel(r"$\omega_R$ [rad/s]")
    for ax in (ax_a, ax_b, ax_c, ax_d):
        ax.grid(True, linewidth=0.3)
        ax.legend(fontsize=8)
    plant = sweep["plant"]
    fig.suptitle(f"{study['figure']} ({study['id']}): {study['title']}\n"
                 f"host simulation, model {sweep['model']}, plant {plant}", fontsize=10)
    fig.tight_layout()
    save_figure(fig, out_dir, study["id"])


def main(argv):
    if len(argv) == 2 and argv[1] == "--check":
        return 0
    if len(argv) != 2:
        sys.stderr.write("usage: plot_sweep.py SWEEP_DIR\n")
        return 2
    out_dir = argv[1]
    try:
        with open(os.path.join(out_dir, "sweep.json")) as f:
            sweep = json.load(f)
        for study in sweep["studies"]:
            plot_study(out_dir, sweep, study)
    except (OSError, ValueError, KeyError) as e:
        sys.stderr.write(f"plot_sweep.py: error: {out_dir}: {e}\n")
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
